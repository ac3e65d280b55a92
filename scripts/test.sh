#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# README command 2: install what is missing, build, run every test tier through ctest
# (GoogleTest for cpp/, pytest for the package, blender_tests/ in headless Blender).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
hf_install_missing
hf_build
cd "$HF_BUILD"
# The last lines count passed, failed and skipped per tier with each skip's reason
# (scripts/test_summary.py). The summary is strict: the command fails when ctest does, when a test
# was not run, when a skip is not one of the expected ones (EXPECTED_SKIPS there: the README's
# test section says which) and, run without arguments (the whole suite), when a tier did not run.
# Arguments go to ctest (e.g. -R NAME, -L LABEL): a selection, so tiers left out are not required.
# HF_TEST_STRICT=0 only prints the summary (the exit status is then ctest's): for a machine that
# lacks a tier on purpose; CI never sets it.
rm -f "$HF_BUILD/ctest-junit.xml" "$HF_BUILD/pytest-junit.xml"
rc=0
ctest --output-on-failure --timeout 2400 --output-junit "$HF_BUILD/ctest-junit.xml" "$@" || rc=$?
strict=(--strict)
[ $# -eq 0 ] && strict+=(--all-tiers)
[ "${HF_TEST_STRICT:-1}" = 0 ] && strict=()
src=0
python3 "$HF_ROOT/scripts/test_summary.py" "${strict[@]}" "$HF_BUILD/ctest-junit.xml" "$HF_BUILD/pytest-junit.xml" || src=$?
[ "$rc" -ne 0 ] && exit "$rc"
exit "$src"
