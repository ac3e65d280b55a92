#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# README command 2: install what is missing, build, run every test tier through ctest
# (GoogleTest for cpp/, pytest for the package, blender_tests/ in headless Blender).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
hf_install_missing
hf_build
cd "$HF_BUILD"
# The last lines count passed, failed and skipped per tier (scripts/test_summary.py), so a tier
# that skipped or was never registered is visible; the exit status is ctest's.
rm -f "$HF_BUILD/ctest-junit.xml" "$HF_BUILD/pytest-junit.xml"
rc=0
ctest --output-on-failure --timeout 2400 --output-junit "$HF_BUILD/ctest-junit.xml" "$@" || rc=$?
python3 "$HF_ROOT/scripts/test_summary.py" "$HF_BUILD/ctest-junit.xml" "$HF_BUILD/pytest-junit.xml" || true
exit "$rc"
