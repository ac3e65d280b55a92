#!/usr/bin/env bash
# README command 2: install what is missing, build, run every test tier through ctest
# (GoogleTest for cpp/, pytest for the package, blender_tests/ in headless Blender).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
hf_install_missing
hf_build
cd "$HF_BUILD"
ctest --output-on-failure --timeout 2400 "$@"
