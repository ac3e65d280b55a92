#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest package_repository_<bpy version>: the static extension repository. scripts/build_extension.sh
# packs the wheels that package_build made into a zip and writes the repository (the zip and
# index.json from Blender's own server-generate, run from this bpy), then repo_check.py adds the
# folder to bpy as a repository, installs and enables hapticfluid from it, publishes a newer
# version into it and upgrades to that.
#   bash test_repository.sh BPY_VERSION PACKAGE_DIR
# Exit 77 (ctest SKIP), reason printed: no wheels were built here, or (where PyPI has no bpy wheels)
# bpy cannot be installed; on Linux x86_64 a bpy that cannot be installed fails the test.
set -euo pipefail
VERSION="$1"
PKG="$(cd "$2" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() { echo "SKIP: $*"; exit 77; }

wheels=("$PKG"/dist/hapticfluid-*.whl)
[ ${#wheels[@]} -ge 2 ] && [ -f "${wheels[0]}" ] \
  || skip "no wheels in $PKG/dist: package_build could not build them on this machine (its output says why)"
source "$HERE/bpy_or_skip.sh"
bpy_python_or_skip "$VERSION"

work="$PKG/repository-$VERSION"
rm -rf "$work"
wheel_args=()
for w in "${wheels[@]}"; do wheel_args+=(--wheel "$w"); done
HF_BPY_PYTHON="$BPY_PY" bash "$HERE/../../scripts/build_extension.sh" "${wheel_args[@]}" \
  --out "$work/dist" --repo "$work/repository"
echo "== index.json"
cat "$work/repository/index.json"
echo
# (Blender's download progress, one line per 16 KiB, is left out of the log.)
env -i HOME="$PKG" PATH=/usr/bin:/bin "$BPY_PY" -I "$HERE/repo_check.py" "$work/repository" "$work/bpy" \
  | { grep -v '^PROGRESS ' || true; }
rm -rf "$work"
