#!/usr/bin/env bash
# README command 1: install what is missing, build, run the headless demo, then bake the demo
# scene (examples/bake_demo.json) to an OpenVDB cache and render its last frame with Cycles.
# Extra arguments go to `python3 -m hapticfluid demo` (see --help). Outputs: out/demo/
# force.csv, density.png (the interactive demo), bake_cache/ (VDB frames) and render.png.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
hf_install_missing
hf_build --target _core
cd "$HF_ROOT"
export PYTHONPATH="$HF_BUILD/python${PYTHONPATH:+:$PYTHONPATH}"
/usr/bin/python3 -m hapticfluid demo "$@"
mkdir -p out/demo
echo "== bake: examples/bake_demo.json -> out/demo/bake_cache"
/usr/bin/python3 -m hapticfluid bake examples/bake_demo.json --cache out/demo/bake_cache
echo "== render: frame 44 with Cycles (CPU, 320x240, 16 samples) -> out/demo/render.png"
blender --background --factory-startup --python-exit-code 1 --python scripts/render_bake.py -- \
  out/demo/bake_cache 44 out/demo/render.png --density 60 >out/demo/render.log 2>&1 \
  || { tail -n 30 out/demo/render.log >&2; exit 1; }
grep "rendered" out/demo/render.log
