"""The render task of a farm job: render a chunk of baked frames in one Blender session.

    blender --background --factory-startup --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid.farm.render_chunk as r; r.main()" -- \
        [--root ROOT] [--size W H] [--samples N] [--density D] CACHE FRAMES OUTDIR

FRAMES is a range expression (``5-8``, as an OpenJD CHUNK[INT] task parameter expands, or a
single frame). Reads the cache's manifest for the domain and the baked frames (a frame not
baked yet is an error, so a render never shows an empty volume), shows the frames as a Volume
with the add-on's smoke material (``hapticfluid_blender.volume``: the add-on must be importable,
installed or on PYTHONPATH), frames the domain with a camera, lights it, and writes
OUTDIR/frame_####.png per frame, each complete or not at all (written under a temporary name,
then renamed). Cycles on the CPU (``--factory-startup`` leaves no GPU compute device enabled).
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import os
import sys
from typing import List, Optional, Sequence

OUTPUT_PATTERN = "frame_{frame:04d}.png"
log = logging.getLogger(__name__)


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    p = argparse.ArgumentParser(prog="render_chunk", description="render baked frames of a hapticfluid cache")
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
        raise SystemExit(f"render_chunk: frame(s) {missing} are not baked in {cache} (baked: "
                         f"{'none' if last is None else f'{first}..{last}'}); bake first or render fewer frames")


def _setup_scene(bpy, manifest: dict, cache: str, args: argparse.Namespace):
    from mathutils import Vector
    from hapticfluid_blender import volume

    sc = manifest["scene"]
    first, last = baked_range(manifest)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    first_file = os.path.join(os.path.abspath(cache), "data", f"fluid_data_{first:04d}.vdb")
    volume.show_sequence(scene, first_file, first, last - first + 1, args.density)

    origin, size = Vector(sc["domain_origin"]), Vector(sc["domain_size"])
    centre = origin + 0.5 * size
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.data.lens = 35.0
    width, height = args.size
    fov = 2 * math.atan(math.tan(0.5 * cam.data.angle) * min(width, height) / max(width, height))
    distance = 0.5 * max(size.z, size.x * height / width) / math.tan(0.5 * fov) + 0.5 * size.y
    cam.location = centre + Vector((0.0, -distance, 0.08 * size.z))  # in front (-y), a little above
    cam.rotation_euler = (centre - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.data.energy = 9.0
    sun.rotation_euler = (math.radians(60), 0.0, math.radians(-80))
    scene.world = bpy.data.worlds.new("World")
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.012, 0.014, 0.018, 1.0)

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Filmic"
    return scene


def render(argv: Sequence[str]) -> List[str]:
    """Render the chunk; returns the files written."""
    import bpy

    from hapticfluid.farm import parse_frames, resolve

    args = parse_args(argv)
    cache = str(resolve(args.root, args.cache))
    outdir = str(resolve(args.root, args.outdir))
    try:
        frames = parse_frames(args.frames)
    except ValueError as exc:
        raise SystemExit(f"render_chunk: {exc}") from None
    manifest_file = os.path.join(cache, "hapticfluid_bake.json")
    if not os.path.isfile(manifest_file):
        raise SystemExit(f"render_chunk: {cache} holds no bake manifest (hapticfluid_bake.json): bake it first")
    with open(manifest_file, encoding="utf-8") as f:
        manifest = json.load(f)
    check_frames(frames, manifest, cache)
    scene = _setup_scene(bpy, manifest, cache, args)
    os.makedirs(outdir, exist_ok=True)
    written = []
    for frame in frames:
        out = os.path.join(outdir, OUTPUT_PATTERN.format(frame=frame))
        tmp = os.path.join(outdir, f".{os.path.basename(out)}.{os.getpid()}.tmp.png")
        scene.frame_set(frame)
        scene.render.filepath = tmp
        bpy.ops.render.render(write_still=True)
        os.replace(tmp, out)  # the PNG appears complete or not at all
        written.append(out)
        log.info("frame %d -> %s", frame, out)
    return written


def main() -> None:
    logging.basicConfig(level=logging.INFO, format="hapticfluid.farm.render_chunk: %(message)s")
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    render(argv)
