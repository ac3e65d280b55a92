# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by the package tests that run bpy: bpy_python_or_skip VERSION sets BPY_PY to the python
# of a venv with bpy VERSION (bpy_venv.sh, installed once and cached); exits 77 (ctest SKIP) where
# bpy cannot exist here and 1 where it should install and does not, the reason printed either way.
# Needs HERE (the tests/package folder).
bpy_python_or_skip() {
  local rc=0
  BPY_PY="$(bash "$HERE/bpy_venv.sh" "$1")" || rc=$?
  if [ "$rc" -eq 77 ]; then echo "SKIP: bpy==$1 is not to be had here (bpy_venv.sh said why, above)"; exit 77; fi
  if [ "$rc" -ne 0 ]; then echo "FAIL: bpy==$1 could not be installed (above)"; exit 1; fi
}
