# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender-side half of the ``mantaflow`` benchmark section: builds the benchmark scene as a
Mantaflow gas simulation, bakes it and writes what it measured as JSON.

Run by :mod:`hapticfluid.bench.mantaflow_loop` (not imported by the package)::

    blender --background --factory-startup --python-exit-code 1 \\
        --python mantaflow_scene.py -- PARAMS.json RESULT.json

PARAMS.json: ``domain_size`` (m, the box has its minimum corner at the origin),
``resolution_max``, ``frames``, ``fps``, ``cache_dir``, ``source_centre``/``source_radius`` (m),
``probe_radius`` (m), ``probe_path`` (one probe centre per frame, m), ``vorticity``,
``open_top`` (optional, default true: the box's top border lets smoke out; false: a closed box).
The gas domain uses fixed time steps (adaptive time stepping off), an OpenVDB cache, no noise;
the source is a smoke inflow sphere, the probe a collision effector keyframed on every frame.
RESULT.json: ``bake_s`` (wall time of the bake operator), ``bake_cpu_s`` (its CPU time, all threads), ``frame_files`` (cache files with
their modification times, s), ``blender_version``.
"""

import json
import os
import sys
import time

import bmesh
import bpy


def _args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 2:
        raise SystemExit("usage: blender --background --python mantaflow_scene.py -- PARAMS.json RESULT.json")
    with open(argv[0], encoding="utf-8") as f:
        return json.load(f), argv[1]


def _box(name, size):
    lx, ly, lz = size
    verts = [(x, y, z) for z in (0.0, lz) for y in (0.0, ly) for x in (0.0, lx)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def _sphere(name, centre, radius):
    # Through bmesh, not bpy.ops: an operator would evaluate the half-built fluid scene.
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=radius)
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    obj.location = centre
    bpy.context.scene.collection.objects.link(obj)
    return obj


def main():
    params, result_path = _args()
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    frames = int(params["frames"])
    scene.render.fps = int(params["fps"])
    scene.render.fps_base = 1.0
    scene.frame_start = 1
    scene.frame_end = frames

    source = _sphere("Source", params["source_centre"], params["source_radius"])
    mod = source.modifiers.new("Fluid", "FLUID")
    mod.fluid_type = "FLOW"
    fs = mod.flow_settings
    fs.flow_type = "SMOKE"
    fs.flow_behavior = "INFLOW"
    fs.flow_source = "MESH"

    path = params["probe_path"]
    probe = _sphere("Probe", path[0], params["probe_radius"])
    mod = probe.modifiers.new("Fluid", "FLUID")
    mod.fluid_type = "EFFECTOR"
    mod.effector_settings.effector_type = "COLLISION"
    for frame, centre in enumerate(path, start=1):
        probe.location = centre
        probe.keyframe_insert(data_path="location", frame=frame)

    # The domain last, so Mantaflow first sees a complete scene.
    domain = _box("Domain", params["domain_size"])
    mod = domain.modifiers.new("Fluid", "FLUID")
    mod.fluid_type = "DOMAIN"
    ds = mod.domain_settings
    ds.domain_type = "GAS"
    ds.resolution_max = int(params["resolution_max"])
    ds.use_adaptive_timesteps = False  # Blender then keeps dt = frame length: one step per frame
    ds.vorticity = float(params["vorticity"])
    ds.use_collision_border_top = not bool(params.get("open_top", True))  # open or closed, as the engine's scene
    ds.use_noise = False
    ds.cache_directory = params["cache_dir"]
    ds.cache_type = "ALL"
    ds.cache_data_format = "OPENVDB"
    ds.cache_frame_start = 1
    ds.cache_frame_end = frames

    scene.frame_set(1)
    bpy.context.view_layer.objects.active = domain
    domain.select_set(True)
    t0 = time.perf_counter()
    cpu0 = time.process_time()  # CPU time of every thread of this process
    with bpy.context.temp_override(object=domain, active_object=domain, scene=scene):
        outcome = bpy.ops.fluid.bake_all()
    bake_s = time.perf_counter() - t0
    bake_cpu_s = time.process_time() - cpu0
    if "FINISHED" not in outcome:
        raise SystemExit(f"bpy.ops.fluid.bake_all() returned {outcome}")

    data_dir = os.path.join(params["cache_dir"], "data")
    files = sorted(n for n in os.listdir(data_dir) if n.startswith("fluid_data_") and n.endswith(".vdb")) \
        if os.path.isdir(data_dir) else []
    result = {
        "bake_s": bake_s,
        "bake_cpu_s": bake_cpu_s,
        "bake_started_at": time.time() - (time.perf_counter() - t0),
        "frame_files": [[n, os.path.getmtime(os.path.join(data_dir, n))] for n in files],
        "blender_version": bpy.app.version_string,
        "domain_resolution": list(ds.domain_resolution) if hasattr(ds, "domain_resolution") else None,
    }
    with open(result_path, "w", encoding="utf-8") as f:
        json.dump(result, f)


main()
