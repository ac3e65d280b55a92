#!/usr/bin/env bash
# The GPU benchmark (issue 20, goal 5), one command for the day a GPU machine is lent:
#   scripts/gpu_bench.sh [OUT_DIR]          (default out/bench/gpu)
# Runs the engine (64^3, 100x100x70, 128^3, 256^3 with Jacobi-40, multigrid-4 and the warm-started
# multigrid solve to 1e-4), readback, pressure, bake and floor sections on a HARDWARE EGL device
# (HAPTICFLUID_EGL_DEVICE=hardware: a machine whose GPU gives no OpenGL 4.5 context fails here
# instead of quietly measuring llvmpipe), prints Markdown tables and writes OUT_DIR/gpu.json and
# OUT_DIR/gpu.png (ms per step against cells, with the targets: a whole step <= 1 ms at 128^3 and
# <= 5 ms at 256^3). Needs the module built by the README's commands (build/python), or HF_BUILD.
# HF_PYTHON: the interpreter the module was built for (default /usr/bin/python3).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
HF_BUILD="${HF_BUILD:-$HF_ROOT/build}"
OUT="${1:-$HF_ROOT/out/bench/gpu}"
mkdir -p "$OUT"
[ -d "$HF_BUILD/python/hapticfluid" ] || { echo "gpu_bench.sh: no module in $HF_BUILD/python: build it first (README)" >&2; exit 2; }
export HAPTICFLUID_EGL_DEVICE=hardware
PYTHONPATH="$HF_BUILD/python" "${HF_PYTHON:-/usr/bin/python3}" -m hapticfluid bench \
  --sections engine,readback,pressure,bake,floor --json "$OUT/gpu.json" --plot "$OUT/gpu.png" --markdown
