# SPDX-License-Identifier: GPL-3.0-or-later
"""The render task's arguments and checks, without Blender (the task itself runs inside Blender:
the add-on's entry point render_main, farm.BLENDER_RENDER_EXPR):

    blender --background --factory-startup --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid_blender as a; a.render_main()" -- \
        [--root ROOT] [--size W H] [--samples N] [--density D] CACHE FRAMES OUTDIR

FRAMES is a range expression (``5-8``, as an OpenJD CHUNK[INT] task parameter expands, or a
single frame). Reads the cache's manifest for the domain and the baked frames (a frame not
baked yet is an error, so a render never shows an empty volume), shows the frames as a Volume
with the add-on's smoke material (the add-on must be importable, installed or on PYTHONPATH),
frames the domain with a camera, lights it (the add-on's render scene), and writes
OUTDIR/frame_####.png per frame, each complete or not at all (written under a temporary name,
then renamed). Cycles on the CPU (``--factory-startup`` leaves no GPU compute device enabled).
"""

from __future__ import annotations

import argparse
import json
import os
from typing import List, Optional, Sequence

OUTPUT_PATTERN = "frame_{frame:04d}.png"


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="farm_render", description="render baked frames of a hapticfluid cache")
    p.add_argument("cache", help="the bake's cache folder (relative to --root, or absolute)")
    p.add_argument("frames", help="frames to render: a range expression such as 5-8")
    p.add_argument("outdir", help="output folder (relative to --root, or absolute)")
    p.add_argument("--root", default=".", help="shared root the relative paths start at")
    p.add_argument("--size", type=int, nargs=2, default=(320, 240), metavar=("W", "H"), help="pixels")
    p.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel")
    p.add_argument("--density", type=float, default=60.0, help="Principled Volume density multiplier")
    return p.parse_args(list(argv))


def baked_range(manifest: dict) -> "tuple[int, Optional[int]]":
    return manifest["scene"]["frame_start"], manifest["last_frame"]


def check_frames(frames: List[int], manifest: dict, cache: str) -> None:
    first, last = baked_range(manifest)
    missing = [f for f in frames if last is None or not first <= f <= last]
    if missing:
        raise SystemExit(f"farm_render: frame(s) {missing} are not baked in {cache} (baked: "
                         f"{'none' if last is None else f'{first}..{last}'}); bake first or render fewer frames")


def read_manifest(cache: str) -> dict:
    """The cache's bake manifest, or SystemExit saying to bake first."""
    manifest_file = os.path.join(cache, "hapticfluid_bake.json")
    if not os.path.isfile(manifest_file):
        raise SystemExit(f"farm_render: {cache} holds no bake manifest (hapticfluid_bake.json): bake it first")
    with open(manifest_file, encoding="utf-8") as f:
        return json.load(f)
