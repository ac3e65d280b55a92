# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene a baked cache is rendered in, shared by the farm's render task (farm_render.py) and
the demo's render (scripts/render_bake.py): the baked frames as a Volume with the add-on's smoke
material, a camera framing the domain from the front, a warm key light from the side (its
self-shadowing shows the smoke's shape), a dark world as fill, Cycles on the CPU.
"""

import math
import os


def setup(bpy, manifest: dict, cache: str, size=(320, 240), samples: int = 16, density: float = 60.0,
          probe_frame=None):
    """Build the render scene in a new empty scene for the cache at ``cache`` (its manifest already
    read), ``size`` pixels, ``samples`` per pixel, ``density`` the volume's density multiplier.
    With ``probe_frame``, a sphere probe is drawn as a dark glossy ball at its pose at that frame."""
    from mathutils import Vector

    from . import volume

    sc = manifest["scene"]
    first, last = sc["frame_start"], manifest["last_frame"]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    first_file = os.path.join(os.path.abspath(cache), "data", f"fluid_data_{first:04d}.vdb")
    volume.show_sequence(scene, first_file, first, last - first + 1, density)
    if probe_frame is not None:
        _probe_ball(bpy, sc.get("probe"), probe_frame)

    origin, edges = Vector(sc["domain_origin"]), Vector(sc["domain_size"])
    centre = origin + 0.5 * edges
    width, height = size
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    cam.data.lens = 35.0
    fov = 2 * math.atan(math.tan(0.5 * cam.data.angle) * min(width, height) / max(width, height))
    distance = 0.5 * max(edges.z, edges.x * height / width) / math.tan(0.5 * fov) + 0.5 * edges.y
    cam.location = centre + Vector((0.0, -distance, 0.08 * edges.z))  # in front (-y), a little above
    cam.rotation_euler = (centre - cam.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.data.energy = 9.0
    sun.data.color = (1.0, 0.95, 0.88)
    sun.rotation_euler = (math.radians(60), 0.0, math.radians(-80))  # from the front right, above
    scene.world = bpy.data.worlds.new("World")
    scene.world.use_nodes = True
    background = scene.world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.012, 0.014, 0.018, 1.0)
    background.inputs["Strength"].default_value = 1.0

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    scene.cycles.volume_step_rate = 1.0
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Filmic"
    return scene


def render_frame(bpy, scene, frame: int, out: str) -> str:
    """Render ``frame`` to the PNG ``out``, which appears complete or not at all (written under a
    temporary name, then renamed). Returns the absolute path."""
    out = os.path.abspath(out)
    os.makedirs(os.path.dirname(out), exist_ok=True)
    tmp = os.path.join(os.path.dirname(out), f".{os.path.basename(out)}.{os.getpid()}.tmp.png")
    scene.frame_set(frame)
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)
    os.replace(tmp, out)
    return out


def _probe_ball(bpy, probe, frame):
    if probe is None or probe.get("shape") != "sphere":
        return
    from hapticfluid.bake import Trajectory

    pose = Trajectory(probe["keys"]).pose(frame)
    radius = probe["radius"] * max(abs(x) for x in pose.scale)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=tuple(pose.translation), segments=48, ring_count=24)
    ball = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    mat = bpy.data.materials.new("Probe")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.05, 0.12, 0.25, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.3
    ball.data.materials.append(mat)
