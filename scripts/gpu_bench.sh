#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The GPU benchmark (issue 20, goal 5), one command for the day a GPU machine is lent:
#   scripts/gpu_bench.sh [OUT_DIR]          (default out/bench/gpu)
# Runs the engine (64^3, 100x100x70, 128^3, 256^3 with Jacobi-40, multigrid-4 and the warm-started
# multigrid solve to 1e-4), readback, pressure, bake and floor sections on a HARDWARE EGL device
# (HAPTICFLUID_EGL_DEVICE=hardware: a machine whose GPU gives no OpenGL 4.5 context fails here
# instead of quietly measuring llvmpipe), prints Markdown tables and writes OUT_DIR/gpu.json and
# OUT_DIR/gpu.png (ms per step against cells, with the targets: a whole step <= 1 ms at 128^3 and
# <= 5 ms at 256^3). Then the same sections (floor aside) on the CPU backend, on the same machine's
# cores: OUT_DIR/cpu.json and cpu.png, so the first GPU run says which backend to pick there. Needs the module built by the README's commands (build/python), or HF_BUILD.
# HF_PYTHON: the interpreter the module was built for (default /usr/bin/python3).
# Then the live session in a windowed Blender (blender_tests/window_test_live_pace.py) at 32^3,
# 64^3 and 100x100x70: viewport redraws/s without a session, replaying Blender's own Mantaflow cache
# and with the session (Mouse mode, a dragged probe), simulation Hz, latency p50, Record keys/s;
# OUT_DIR/live/live_pace_<res>.json. The window is the display in $DISPLAY if one is set (a GPU's
# X server), else Xvfb's (llvmpipe draws the viewport; the simulation still runs on the GPU).
# HF_BENCH_LIVE=0 skips it; HF_LIVE_SECONDS sets each phase's length (default 15).
set -euo pipefail

HF_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
HF_BUILD="${HF_BUILD:-$HF_ROOT/build}"
OUT="${1:-$HF_ROOT/out/bench/gpu}"
mkdir -p "$OUT"
[ -d "$HF_BUILD/python/hapticfluid" ] || { echo "gpu_bench.sh: no module in $HF_BUILD/python: build it first (README)" >&2; exit 2; }
export HAPTICFLUID_EGL_DEVICE=hardware
echo "== the GPU backend"
HAPTICFLUID_BACKEND=gpu PYTHONPATH="$HF_BUILD/python" "${HF_PYTHON:-/usr/bin/python3}" -m hapticfluid bench \
  --sections engine,readback,pressure,bake,floor --json "$OUT/gpu.json" --plot "$OUT/gpu.png" --markdown
echo "== the CPU backend"
HAPTICFLUID_BACKEND=cpu PYTHONPATH="$HF_BUILD/python" "${HF_PYTHON:-/usr/bin/python3}" -m hapticfluid bench \
  --sections engine,readback,pressure,bake --json "$OUT/cpu.json" --plot "$OUT/cpu.png" --markdown

[ "${HF_BENCH_LIVE:-1}" = "0" ] && exit 0
command -v blender >/dev/null 2>&1 || { echo "gpu_bench.sh: no blender: the live-session section is skipped" >&2; exit 0; }
window=()
if [ -z "${DISPLAY:-}" ]; then
  command -v xvfb-run >/dev/null 2>&1 || { echo "gpu_bench.sh: no DISPLAY and no xvfb-run: the live-session section is skipped" >&2; exit 0; }
  window=(xvfb-run -a -s "-screen 0 1280x800x24")
fi
mkdir -p "$OUT/live"
status=0
for grid in 32:1.0 64:1.0 100:0.7; do
  res="${grid%%:*}" height="${grid##*:}"
  echo "== live session in a window at resolution $res (domain height $height m)"
  PATH="$(dirname "$(command -v blender)"):$PATH" PYTHONPATH="$HF_BUILD/python:$HF_ROOT/blender_tests" \
    HAPTICFLUID_SOURCE_DIR="$HF_ROOT" HAPTICFLUID_OUT_DIR="$OUT/live" HAPTICFLUID_PACE_RESOLUTION="$res" \
    HAPTICFLUID_PACE_HEIGHT="$height" HAPTICFLUID_PACE_SECONDS="${HF_LIVE_SECONDS:-15}" \
    timeout 900 "${window[@]}" blender --factory-startup --python-use-system-env --enable-event-simulate \
      --python-exit-code 1 --python "$HF_ROOT/blender_tests/window_test_live_pace.py" 2>&1 \
    | grep -E "^(measured|live pace|FAILED|ok: Mantaflow)" || status=1
done
exit $status
