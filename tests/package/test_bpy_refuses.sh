#!/usr/bin/env bash
# ctest package_bpy_refuses_<version>: a bpy older than the manifest's blender_version_min refuses
# the extension zip and names the version it needs (bpy_refuses.py).
#   bash test_bpy_refuses.sh BPY_VERSION PACKAGE_DIR
# Exit 77 (ctest SKIP) as test_bpy.sh: no zip built here, or no bpy wheels for this platform.
set -euo pipefail
VERSION="$1"
PKG="$(cd "$2" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() { echo "SKIP: $*"; exit 77; }
zips=("$PKG"/dist/hapticfluid-*.zip)
[ -f "${zips[0]}" ] || skip "no extension zip in $PKG/dist: package_build could not build one on this machine (its output says why)"
set +e
BPY_PY="$(bash "$HERE/bpy_venv.sh" "$VERSION")"
rc=$?
set -e
[ $rc -eq 77 ] && skip "bpy==$VERSION is not to be had here (bpy_venv.sh said why, above)"
[ $rc -eq 0 ] || { echo "FAIL: bpy==$VERSION could not be installed (above)"; exit 1; }
work="$PKG/bpy-$VERSION-refuses"
rm -rf "$work"
env -i HOME="$PKG" PATH=/usr/bin:/bin "$BPY_PY" -I "$HERE/bpy_refuses.py" "${zips[0]}" "$work"
rm -rf "$work"
