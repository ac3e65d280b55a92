#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# README command 1: install what is missing, build, run the headless demo, then bake the demo
# scene (examples/bake_demo.json) to an OpenVDB cache and render its last frame with Cycles.
# Extra arguments go to `python3 -m hapticfluid demo` (see --help). Outputs: out/demo/
# force.csv, density.png (the interactive demo), bake_cache/ (VDB frames) and render.png.
# With a display ($DISPLAY or $WAYLAND_DISPLAY set) it instead opens Blender on the live demo scene
# (scripts/live_demo.py: add-on from this tree, session running on the simulated Falcon, smoke drawn
# in the viewport); arguments then go to live_demo.py (e.g. --device MOUSE).
# HF_DEMO_LIVE=0 runs the headless demo on a machine with a display; HF_DEMO_LIVE=1 insists on Blender.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
case "${HF_DEMO_LIVE:-auto}" in
  0) hf_live=0 ;;
  1|auto)
    if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then hf_live=1; else hf_live=0; fi
    if [ "${HF_DEMO_LIVE:-auto}" = 1 ] && [ "$hf_live" = 0 ]; then
      echo "error: HF_DEMO_LIVE=1 opens Blender and needs a display, but \$DISPLAY and \$WAYLAND_DISPLAY are empty" >&2
      exit 1
    fi ;;
  *) echo "error: HF_DEMO_LIVE must be 0, 1 or auto (the default), got '$HF_DEMO_LIVE'" >&2; exit 1 ;;
esac
hf_install_missing
hf_build --target _core
cd "$HF_ROOT"
# Blender reads PYTHONPATH only with --python-use-system-env (Blender 4.3 on Debian 13, upstream builds).
export PYTHONPATH="$HF_BUILD/python${PYTHONPATH:+:$PYTHONPATH}"
if [ "$hf_live" = 1 ]; then
  echo "== live: Blender with the demo scene and the session running (Esc stops it; HF_DEMO_LIVE=0 for the headless demo)"
  exec blender --factory-startup --python-use-system-env --python scripts/live_demo.py -- "$@"
fi
/usr/bin/python3 -m hapticfluid demo "$@"
mkdir -p out/demo
echo "== bake: examples/bake_demo.json -> out/demo/bake_cache"
/usr/bin/python3 -m hapticfluid bake examples/bake_demo.json --cache out/demo/bake_cache
echo "== render: frame 44 with Cycles (CPU, 320x240, 16 samples) -> out/demo/render.png"
blender --background --factory-startup --python-use-system-env --python-exit-code 1 --python scripts/render_bake.py -- \
  out/demo/bake_cache 44 out/demo/render.png --density 60 >out/demo/render.log 2>&1 \
  || { tail -n 30 out/demo/render.log >&2; exit 1; }
grep "rendered" out/demo/render.log
