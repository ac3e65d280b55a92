"""Render one frame of a hapticfluid bake with Cycles on the CPU (used by scripts/demo.sh):

    blender --background --factory-startup --python-use-system-env --python scripts/render_bake.py -- CACHE FRAME OUT.png \
        [--size 320 240] [--samples 16] [--density 30]

Reads the cache's manifest for the domain and frame range, shows the frames as a Volume with
the add-on's smoke material, frames the domain with a camera and lights it, and writes OUT.png.
"""

import argparse
import json
import math
import os
import sys

import bpy
from mathutils import Vector

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))

from hapticfluid_blender import volume  # noqa: E402


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
    sc = manifest["scene"]
    first, last = sc["frame_start"], manifest["last_frame"]
    if last is None or not first <= args.frame <= last:
        raise SystemExit(f"frame {args.frame} is not baked in {args.cache} (frames {first}..{last})")

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    first_file = os.path.join(os.path.abspath(args.cache), "data", f"fluid_data_{first:04d}.vdb")
    volume.show_sequence(scene, first_file, first, last - first + 1, args.density)

    probe = sc.get("probe")
    if probe is not None and probe.get("shape") == "sphere":  # a dark glossy ball at its pose then
        from hapticfluid.bake import Trajectory

        pose = Trajectory(probe["keys"]).pose(args.frame)
        radius = probe["radius"] * max(abs(x) for x in pose.scale)
        bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=tuple(pose.translation), segments=48,
                                             ring_count=24)
        ball = bpy.context.active_object
        bpy.ops.object.shade_smooth()
        mat = bpy.data.materials.new("Probe")
        mat.use_nodes = True
        bsdf = mat.node_tree.nodes["Principled BSDF"]
        bsdf.inputs["Base Color"].default_value = (0.05, 0.12, 0.25, 1.0)
        bsdf.inputs["Roughness"].default_value = 0.3
        ball.data.materials.append(mat)

    origin = Vector(sc["domain_origin"])
    size = Vector(sc["domain_size"])
    centre = origin + 0.5 * size
    # Camera in front (-y), slightly above, fitting the box's height with a margin.
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.data.lens = 35.0
    fov = 2 * math.atan(math.tan(0.5 * cam.data.angle) * min(args.size) / max(args.size))
    distance = 0.5 * max(size.z, size.x * args.size[1] / args.size[0]) / math.tan(0.5 * fov) + 0.5 * size.y
    cam.location = centre + Vector((0.0, -distance, 0.08 * size.z))
    cam.rotation_euler = (centre - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    # A warm key light from the side (self-shadowing shows the smoke's shape), a dark world as fill.
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.data.energy = 9.0
    sun.data.color = (1.0, 0.95, 0.88)
    sun.rotation_euler = (math.radians(60), 0.0, math.radians(-80))  # from the front right, above
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.012, 0.014, 0.018, 1.0)
    bg.inputs["Strength"].default_value = 1.0

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    scene.cycles.volume_step_rate = 1.0
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Filmic"
    scene.frame_set(args.frame)
    out = os.path.abspath(args.out)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    tmp = os.path.join(os.path.dirname(out), "." + os.path.basename(out) + ".tmp.png")
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)
    os.replace(tmp, out)  # the PNG appears complete or not at all
    print(f"rendered frame {args.frame} of {args.cache} to {out}")


main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
