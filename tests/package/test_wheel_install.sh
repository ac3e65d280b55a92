#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest package_wheel_install_<tag>: the TAG wheel (cp311 or cp313) that package_build put in
# PACKAGE_DIR/dist goes into a new virtual environment of that CPython (numpy from PyPI), then a process whose environment hides the build
# tree (env -i, python -I, run from an empty folder) imports it, steps a 16^3 simulation,
# writes a VDB that the system's OpenVDB reads back (vdb_print) and checks the module's ELF
# tables: OpenVDB, TBB, blosc, Imath and libusb inside
# it and hidden, nothing needed of the system beyond glibc 2.28 and libglvnd (wheel_check.py).
#   bash test_wheel_install.sh TAG PACKAGE_DIR
# Exit 77 (ctest SKIP): no wheel could be built here, or pip cannot reach its index for numpy;
# reason printed. numpy failing to install with the index reachable fails the test.
set -euo pipefail
TAG="$1"
PKG="$(cd "$2" && pwd)"
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
skip() { echo "SKIP: $*"; exit 77; }
source "$HERE/../../scripts/package_common.sh"

wheels=("$PKG"/dist/hapticfluid-*-"$TAG"-*.whl)
[ -f "${wheels[0]}" ] || skip "no $TAG wheel in $PKG/dist: package_build could not build one on this machine (its output says why)"
wheel="${wheels[0]}"
pyver="${TAG#cp3}"; pyver="3.$pyver"
PY="$(hf_python "$pyver")" || skip "no CPython $pyver with venv and ensurepip"

VENV="$PKG/clean-venv-$TAG"
rm -rf "$VENV"
t0=$(date +%s%N)
"$PY" -m venv "$VENV"
if ! "$VENV/bin/python" -m pip install -q numpy >"$PKG/pip-numpy-$TAG.log" 2>&1; then
  hf_pip_quiet <"$PKG/pip-numpy-$TAG.log" | tail -n 20
  hf_pip_offline "$PKG/pip-numpy-$TAG.log" && skip "numpy cannot be installed: pip could not reach its package index (no network)"
  echo "error: numpy cannot be installed with pip's index reachable (above)"; exit 1
fi
"$VENV/bin/python" -c "import numpy" || { echo "error: numpy installed but does not import (above)"; exit 1; }
"$VENV/bin/python" -m pip install -q --no-index "$wheel" 2>&1 | hf_pip_quiet
t1=$(date +%s%N)
run_dir="$(mktemp -d)"
cd "$run_dir"
env -i HOME="$run_dir" PATH=/usr/bin:/bin HF_VENV="$VENV" HF_RUN_DIR="$run_dir" HF_VDB_READBACK="${HF_VDB_READBACK:-1}" \
  "$VENV/bin/python" -I "$HERE/wheel_check.py"
t2=$(date +%s%N)
echo "wheel $(basename "$wheel") ($(du -h "$wheel" | cut -f1)): venv + install $(( (t1 - t0) / 1000000 )) ms," \
     "import + 3 steps of 16^3 + VDB $(( (t2 - t1) / 1000000 )) ms"
cd / && rm -rf "$run_dir"
