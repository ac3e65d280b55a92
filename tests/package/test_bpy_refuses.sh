#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
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
source "$HERE/bpy_or_skip.sh"
bpy_python_or_skip "$VERSION"
work="$PKG/bpy-$VERSION-refuses"
rm -rf "$work"
env -i HOME="$PKG" PATH=/usr/bin:/bin "$BPY_PY" -I "$HERE/bpy_refuses.py" "${zips[0]}" "$work"
rm -rf "$work"
