#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest package_wheel_glibc_2.31: the cp311 wheel that package_build put in PACKAGE_DIR/dist
# passes every check of test_wheel_install.sh (clean venv, import, 16^3 steps on Mesa's llvmpipe,
# a VDB written, the module's ELF tables) on Debian 11 (bullseye, glibc 2.31: the oldest glibc
# in Debian's archive; Ubuntu 20.04 has the same), not only on the build machine's glibc 2.36.
#   bash test_old_glibc.sh PACKAGE_DIR
# The bullseye tree is built once with mmdebstrap into
# ${HF_BULLSEYE_TREE:-~/.cache/hapticfluid/bullseye-glibc2.31} (what building CPython needs,
# binutils, libglvnd and Mesa) and kept; bullseye has no CPython 3.11, so scripts/build_python.sh
# builds one inside it from bookworm's source package, once (kept in the tree). Entered through
# scripts/debian13_check.sh (chroot: needs root), which enters any Debian tree it is given.
# Exit 77 (ctest SKIP), reason printed: no cp311 wheel was built here, or no bullseye tree can be
# had on this machine (not Debian, not root, no mmdebstrap). A tree that cannot be built on a
# Debian host that has mmdebstrap as root fails the test.
set -euo pipefail
PKG="$(cd "$1" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
HF_ROOT="$(cd "$HERE/../.." && pwd)"
skip() { echo "SKIP: $*"; exit 77; }

wheels=("$PKG"/dist/hapticfluid-*-cp311-*.whl)
[ -f "${wheels[0]}" ] || skip "no cp311 wheel in $PKG/dist: package_build could not build one on this machine (its output says why)"
wheel="${wheels[0]}"

[ -f /etc/debian_version ] || skip "not a Debian host: the bullseye tree is built with mmdebstrap"
[ "$(id -u)" -eq 0 ] || skip "not root: the bullseye tree is entered with chroot (run the test command as root, or sudo)"
command -v mmdebstrap >/dev/null 2>&1 || skip "mmdebstrap is missing (the README's test command installs it: scripts/common.sh)"

tree="${HF_BULLSEYE_TREE:-$HOME/.cache/hapticfluid/bullseye-glibc2.31}"
# What scripts/build_python.sh needs to build CPython, binutils for wheel_check.py's ELF checks,
# and libglvnd with Mesa (llvmpipe) for the engine.
packages=git,ca-certificates,gcc,make,binutils,libc6-dev,libssl-dev,zlib1g-dev,libffi-dev,libbz2-dev
packages+=,liblzma-dev,libsqlite3-dev,uuid-dev,libreadline-dev,libncurses-dev,libexpat1-dev,xz-utils
packages+=,libegl1,libopengl0,libegl-mesa0,libgl1-mesa-dri
if [ ! -f "$tree/.hf-packages" ] || [ "$(cat "$tree/.hf-packages")" != "$packages" ]; then
  echo "== building the bullseye tree: $tree"
  rm -rf "$tree.part"
  mkdir -p "$(dirname "$tree")"
  t0=$SECONDS
  # Built beside and moved into place whole: an interrupted build leaves no half tree behind.
  if ! mmdebstrap --variant=minbase --include="$packages" bullseye "$tree.part" http://deb.debian.org/debian \
      >"$tree.log" 2>&1; then
    tail -n 30 "$tree.log"
    rm -rf "$tree.part"
    echo "FAIL: mmdebstrap could not build the bullseye tree (log above: $tree.log)"
    exit 1
  fi
  echo "$packages" >"$tree.part/.hf-packages"
  rm -rf "$tree"
  mv "$tree.part" "$tree"
  echo "bullseye tree: $((SECONDS - t0)) s, $(du -sh "$tree" | cut -f1)"
fi

rm -rf "$tree/root/pkg"
mkdir -p "$tree/root/pkg/dist"
cp "$wheel" "$tree/root/pkg/dist/"
logs="$(mktemp -d)"
rc=0
# CPython 3.11 first (built once, about 6 minutes), then the wheel's checks under glibc 2.31.
bash "$HF_ROOT/scripts/debian13_check.sh" --root "$tree" --reuse --logs "$logs" -- \
  'echo "glibc $(getconf GNU_LIBC_VERSION), Debian $(cat /etc/debian_version)" && bash scripts/build_python.sh 3.11 && HF_VDB_READBACK=0 bash tests/package/test_wheel_install.sh cp311 /root/pkg' \
  || rc=$?
cat "$logs"/*.log
rm -rf "$logs" "$tree/root/pkg"
exit "$rc"
