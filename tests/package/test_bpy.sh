#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest package_bpy_<version>: Blender as a Python module (bpy from PyPI) with the extension zip
# that package_build put in PACKAGE_DIR/dist: Blender's validator accepts the zip, then
# bpy_check.py runs twice in fresh processes (bpy imported first, then hapticfluid first):
# install + enable the extension (Blender picks the zip's wheel for its own Python: cp311 for
# 4.2 to 5.0, cp313 for 5.1+), give roles through the Physics tab's operator, bake 3 frames
# through the operator, load the Volume, run a live session on the simulated Falcon through its
# operators (snapshots, a non-zero force, Record), step the engine and read its VDB back through
# bpy, disable the add-on.
#   bash test_bpy.sh BPY_VERSION PACKAGE_DIR
# bpy is ~0.4 GB per release: it is installed once into a venv kept in
# ${HF_BPY_CACHE:-~/.cache/hapticfluid}/bpy-<version> and reused by later runs (tests/package/
# bpy_venv.sh; the CPython it needs, 3.11 or 3.13, from scripts/build_python.sh).
# Exit 77 (ctest SKIP), reason printed: no extension zip was built here, or (only where PyPI has
# no bpy wheels: not Linux x86_64 with glibc 2.28+) this bpy release cannot be installed. On
# Linux x86_64 a bpy that cannot be installed or imported fails the test.
set -euo pipefail
VERSION="$1"
PKG="$(cd "$2" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() { echo "SKIP: $*"; exit 77; }
source "$HERE/../../scripts/package_common.sh"

zips=("$PKG"/dist/hapticfluid-*.zip)
[ -f "${zips[0]}" ] || skip "no extension zip in $PKG/dist: package_build could not build one on this machine (its output says why)"
zip="${zips[0]}"

source "$HERE/bpy_or_skip.sh"
bpy_python_or_skip "$VERSION"
env -i HOME="$PKG" PATH=/usr/bin:/bin "$BPY_PY" -I "$HERE/extension_cli.py" validate "$zip"
for order in bpy-first hapticfluid-first; do
  work="$PKG/bpy-$VERSION-$order"
  rm -rf "$work"
  echo "== bpy $VERSION, $order"
  env -i HOME="$PKG" PATH=/usr/bin:/bin "$BPY_PY" -I "$HERE/bpy_check.py" "$order" "$zip" "$work"
  rm -rf "$work"
done
