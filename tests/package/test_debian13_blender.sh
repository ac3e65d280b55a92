#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest package_debian13_blender: Debian 13's own Blender (4.3, Python 3.13, the distribution's
# binary, not a bpy module) installs the extension zip that package_build put in PACKAGE_DIR/dist
# and passes every check of tests/package/test_blender.sh (Blender's validator, then install,
# roles, bake, Volume, live session on the simulated Falcon, Record, disable).
#   bash test_debian13_blender.sh PACKAGE_DIR
# Where the system's `blender` is 4.2 or newer (Debian 13 itself) it runs with that one. On a
# Debian host with an older Blender (Debian 12's 3.4: the project's machines) it runs in a trixie
# tree with Debian's blender package, built once with mmdebstrap (104 s here, 1.4 GB) into
# ${HF_TRIXIE_BLENDER:-~/.cache/hapticfluid/trixie-blender} and kept, entered through
# scripts/debian13_check.sh (chroot: needs root). The tree carries libegl1 and libopengl0, which
# Debian's blender package does not pull in and the wheels leave to the system (docs/WHEELS.md).
# Exit 77 (ctest SKIP), reason printed: no zip was built here, or no Debian 13 Blender can be had
# on this machine (not Debian, not root, no mmdebstrap). A tree that cannot be built on a Debian
# host that has mmdebstrap as root fails the test.
set -euo pipefail
PKG="$(cd "$1" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
HF_ROOT="$(cd "$HERE/../.." && pwd)"
skip() { echo "SKIP: $*"; exit 77; }

zips=("$PKG"/dist/hapticfluid-*.zip)
[ -f "${zips[0]}" ] || skip "no extension zip in $PKG/dist: package_build could not build one on this machine (its output says why)"
zip="${zips[0]}"

# Debian 13 itself: its Blender is the system's.
system_version="$(blender --version 2>/dev/null | sed -n 's/^Blender \([0-9]*\.[0-9]*\).*/\1/p' | head -1)" || true
if [ -n "$system_version" ] && [ "$(printf '%s\n4.2\n' "$system_version" | sort -V | head -1)" = 4.2 ]; then
  exec bash "$HERE/test_blender.sh" "$zip" blender
fi

[ -f /etc/debian_version ] || skip "not a Debian host: Debian 13's Blender comes from a trixie tree built with mmdebstrap"
[ "$(id -u)" -eq 0 ] || skip "not root: the trixie tree is entered with chroot (run the test command as root, or sudo)"
command -v mmdebstrap >/dev/null 2>&1 || skip "mmdebstrap is missing (the README's test command installs it: scripts/common.sh)"

tree="${HF_TRIXIE_BLENDER:-$HOME/.cache/hapticfluid/trixie-blender}"
if [ ! -x "$tree/usr/bin/blender" ]; then
  echo "== building the trixie tree with Debian's blender: $tree"
  rm -rf "$tree.part"
  mkdir -p "$(dirname "$tree")"
  t0=$SECONDS
  # Built beside and moved into place whole: an interrupted build leaves no half tree behind.
  if ! mmdebstrap --variant=minbase \
      --include=git,ca-certificates,blender,libegl1,libopengl0,libegl-mesa0,libgl1-mesa-dri,python3-numpy \
      trixie "$tree.part" http://deb.debian.org/debian >"$tree.log" 2>&1; then
    tail -n 30 "$tree.log"
    rm -rf "$tree.part"
    echo "FAIL: mmdebstrap could not build the trixie tree (log above: $tree.log)"
    exit 1
  fi
  rm -rf "$tree"
  mv "$tree.part" "$tree"
  echo "trixie tree: $((SECONDS - t0)) s, $(du -sh "$tree" | cut -f1)"
fi

name="$(basename "$zip")"
cp "$zip" "$tree/root/$name"
logs="$(mktemp -d)"
rc=0
bash "$HF_ROOT/scripts/debian13_check.sh" --root "$tree" --reuse --logs "$logs" -- \
  bash tests/package/test_blender.sh "/root/$name" || rc=$?
cat "$logs"/*.log
rm -rf "$logs" "$tree/root/$name"
exit "$rc"
