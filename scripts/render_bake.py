# SPDX-License-Identifier: GPL-3.0-or-later
"""Render one frame of a hapticfluid bake with Cycles on the CPU (used by scripts/demo.sh):

    blender --background --factory-startup --python-use-system-env --python scripts/render_bake.py -- CACHE FRAME OUT.png \
        [--size 320 240] [--samples 16] [--density 30]

Reads the cache's manifest for the domain and frame range and renders the frame in the add-on's
render scene (hapticfluid_blender.render.render_scene, as the farm's render task does) with the probe
drawn as a dark ball, to OUT.png.
"""

import argparse
import json
import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

from hapticfluid_blender.render import render_scene  # noqa: E402


def main(argv):
    p = argparse.ArgumentParser(prog="render_bake.py")
    p.add_argument("cache")
    p.add_argument("frame", type=int)
    p.add_argument("out")
    p.add_argument("--size", type=int, nargs=2, default=(320, 240))
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--density", type=float, default=60.0, help="Principled Volume density multiplier")
    args = p.parse_args(argv)

    with open(os.path.join(args.cache, "hapticfluid_bake.json"), encoding="utf-8") as f:
        manifest = json.load(f)
    first, last = manifest["scene"]["frame_start"], manifest["last_frame"]
    if last is None or not first <= args.frame <= last:
        raise SystemExit(f"frame {args.frame} is not baked in {args.cache} (frames {first}..{last})")
    scene = render_scene.setup(bpy, manifest, args.cache, size=tuple(args.size), samples=args.samples,
                               density=args.density, probe_frame=args.frame)
    out = render_scene.render_frame(bpy, scene, args.frame, args.out)
    print(f"rendered frame {args.frame} of {args.cache} to {out}")


main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
