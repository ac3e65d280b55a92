#!/usr/bin/env bash
# ctest package_bpy_<version>: Blender as a Python module (bpy from PyPI) with the extension zip
# that package_build put in PACKAGE_DIR/dist: Blender's validator accepts the zip, then
# bpy_check.py runs twice in fresh processes (bpy imported first, then hapticfluid first):
# install + enable the extension, bake 3 frames through the operator, load the Volume, step the
# engine and read its VDB back through bpy.
#   bash test_bpy.sh BPY_VERSION PACKAGE_DIR
# bpy is ~0.4 GB per release: it is installed once into a venv kept in
# ${HF_BPY_CACHE:-~/.cache/hapticfluid}/bpy-<version> and reused by later runs.
# Exit 77 (ctest SKIP), reason printed: no extension zip was built here, or this bpy release
# cannot be installed or imported on this machine.
set -euo pipefail
VERSION="$1"
PKG="$(cd "$2" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() { echo "SKIP: $*"; exit 77; }
source "$HERE/../../scripts/package_common.sh"

zips=("$PKG"/dist/hapticfluid-*.zip)
[ -f "${zips[0]}" ] || skip "no extension zip in $PKG/dist: package_build could not build one on this machine (its output says why)"
zip="${zips[0]}"

CACHE="${HF_BPY_CACHE:-$HOME/.cache/hapticfluid}/bpy-$VERSION"
if [ ! -f "$CACHE/.hf-ok" ]; then
  PY="$(hf_python311)" || skip "no CPython 3.11 with venv and ensurepip for bpy $VERSION"
  echo "== installing bpy==$VERSION into $CACHE (once; about 0.4 GB)"
  t0=$(date +%s)
  rm -rf "$CACHE"
  mkdir -p "$(dirname "$CACHE")"
  "$PY" -m venv "$CACHE"
  if ! "$CACHE/bin/python" -m pip install -q "bpy==$VERSION" >"$CACHE.log" 2>&1; then
    reason="$(hf_pip_quiet <"$CACHE.log" | tail -3)"
    rm -rf "$CACHE"
    skip "bpy==$VERSION cannot be installed here: $reason"
  fi
  if ! err="$("$CACHE/bin/python" -c 'import bpy' 2>&1)"; then
    rm -rf "$CACHE"
    skip "bpy==$VERSION installs but does not import here: $(echo "$err" | tail -2)"
  fi
  touch "$CACHE/.hf-ok"
  echo "   installed in $(( $(date +%s) - t0 )) s"
fi

env -i HOME="$PKG" PATH=/usr/bin:/bin "$CACHE/bin/python" -I "$HERE/validate_extension.py" "$zip"
for order in bpy-first hapticfluid-first; do
  work="$PKG/bpy-$VERSION-$order"
  rm -rf "$work"
  echo "== bpy $VERSION, $order"
  env -i HOME="$PKG" PATH=/usr/bin:/bin "$CACHE/bin/python" -I "$HERE/bpy_check.py" "$order" "$zip" "$work"
  rm -rf "$work"
done
