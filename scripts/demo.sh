#!/usr/bin/env bash
# README command 1: install what is missing, build, run the headless demo.
# Extra arguments go to `python3 -m hapticfluid demo` (see --help).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
hf_install_missing
hf_build --target _core
cd "$HF_ROOT"
PYTHONPATH="$HF_BUILD/python${PYTHONPATH:+:$PYTHONPATH}" exec /usr/bin/python3 -m hapticfluid demo "$@"
