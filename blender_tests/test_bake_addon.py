# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: the add-on bakes an
animated probe through a smoke plume (Bake operator, synchronous in background mode), the
frames load as a Volume sequence with the right grids and bounds, Cycles renders the smoke,
bake_blend.py bakes a saved .blend from the command line, and Free deletes the frames."""

import os
import shutil
import subprocess
import tempfile

import bpy

from support import SOURCE_DIR as SOURCE, bake_scene, check, refused

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)


def build_scene(cache_dir):
    scene, s, _, _, source = bake_scene(cache_dir)
    source.hide_render = True
    s.write_velocity = True
    s.tolerance = 0.0
    s.heat_buoyancy, s.source_temperature, s.density_scale = 2.0, 10.0, 40.0
    return scene, s


def main():
    hapticfluid_blender.register()
    tmp = tempfile.mkdtemp(prefix="hf_blender_bake_")
    cache = os.path.join(tmp, "cache")
    scene, s = build_scene(cache)

    # The pressure solver settings reach the bake's scene description.
    from hapticfluid_blender.bake import blender_scene

    s.pressure_solver, s.pressure_iterations = "MULTIGRID", 4
    fluid = blender_scene.scene_dict(scene, s)["fluid"]
    check(fluid["pressure_solver"] == "multigrid" and fluid["pressure_iterations"] == 4
          and abs(fluid["pressure_tolerance"] - 1e-3) < 1e-9, f"pressure solver settings in the scene: {fluid}")

    result = bpy.ops.hapticfluid.bake()
    check(result == {"FINISHED"}, f"Bake operator finished ({result}, status: {s.status})")
    files = sorted(os.listdir(os.path.join(cache, "data")))
    check(files == [f"fluid_data_{f:04d}.vdb" for f in range(1, 5)], f"four frame files: {files}")
    check(s.volume_object is not None and s.volume_object.type == "VOLUME", "a Volume object shows the bake")

    obj = s.volume_object
    vol = obj.data
    check(vol.is_sequence and vol.frame_duration == 4, "the volume is a 4-frame sequence")
    check(obj.active_material is not None and any(
        n.bl_idname == "ShaderNodeVolumePrincipled" for n in obj.active_material.node_tree.nodes),
        "the volume has a Principled Volume material")
    for frame in (2, 4):
        scene.frame_set(frame)
        deps = bpy.context.evaluated_depsgraph_get()
        ev = obj.evaluated_get(deps)
        grids = ev.data.grids
        check(grids.load(), f"frame {frame}: grids load")
        names = {g.name: g.data_type for g in grids}
        check(names.get("density") == "FLOAT" and names.get("velocity") == "VECTOR_FLOAT",
              f"frame {frame}: grids density (float) and velocity (vector): {names}")
        check(grids.frame_filepath.endswith(f"fluid_data_{frame:04d}.vdb"),
              f"scene frame {frame} reads {os.path.basename(grids.frame_filepath)}")
        corners = [obj.matrix_world @ __import__("mathutils").Vector(c) for c in ev.bound_box]
        lo = [min(c[i] for c in corners) for i in range(3)]
        hi = [max(c[i] for c in corners) for i in range(3)]
        h = 1.0 / 24
        check(all(-h <= lo[i] <= h and 1 - h <= hi[i] <= 1 + h for i in range(3)),
              f"frame {frame}: the volume's bounds {lo} .. {hi} are the domain 0..1 m (within a cell)")
        # Exact alignment as Blender reads it: voxel (i, j, k) -> origin + (i + 1/2) h, the
        # simulation's cell centre (a half-cell shift would pass the bounds check above).
        for g in grids:
            m = obj.matrix_world @ g.matrix_object
            check(all(abs(m[a][a] - h) < 1e-6 and abs(m[a][3] - 0.5 * h) < 1e-6 for a in range(3)),
                  f"frame {frame}: grid {g.name} puts voxel centres on the cell centres: {[list(r) for r in m]}")

    # Cycles renders the smoke (the domain is hidden from render after the bake).
    check(s.domain.hide_render, "the domain mesh is hidden from render")
    scene.frame_set(4)
    cam_data = bpy.data.cameras.new("cam")
    cam = bpy.data.objects.new("cam", cam_data)
    scene.collection.objects.link(cam)
    cam.location = (0.5, -2.2, 0.5)
    cam.rotation_euler = (1.5708, 0.0, 0.0)
    scene.camera = cam
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    scene.cycles.use_denoising = False
    scene.render.film_transparent = True
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 40, 40, 100
    png = os.path.join(tmp, "render.png")
    scene.render.filepath = png
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(png)
    alpha = list(img.pixels)[3::4]
    covered = sum(1 for a in alpha if a > 0.05)
    check(covered > 20, f"Cycles renders the smoke: {covered} of {len(alpha)} pixels covered")

    # A saved .blend bakes from the command line with bake_blend.py.
    s.cache_dir = "//cli_cache"
    blend = os.path.join(tmp, "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    script = os.path.join(SOURCE, "addon", "hapticfluid_blender", "bake", "bake_blend.py")
    run = subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", "--python-use-system-env", blend,
                          "--python-exit-code", "1",
                          "--python", script, "--", "--resolution", "16"],
                         capture_output=True, text=True, timeout=300)
    print(run.stdout[-2000:], run.stderr[-2000:])
    check(run.returncode == 0, "bake_blend.py exits 0")
    cli_files = sorted(os.listdir(os.path.join(tmp, "cli_cache", "data")))
    check(len(cli_files) == 4, f"bake_blend.py wrote the frames next to the .blend: {cli_files}")

    # Free deletes the bake's files.
    s.cache_dir = cache
    check(bpy.ops.hapticfluid.bake_free() == {"FINISHED"}, "Free operator finished")
    check(not os.path.exists(os.path.join(cache, "data")), "Free removed the frames")

    # A missing cache parent is reported before any work.
    s.cache_dir = os.path.join(tmp, "missing", "deeper", "cache")
    refused(bpy.ops.hapticfluid.bake, "does not exist")  # background mode: an ERROR report raises
    hapticfluid_blender.unregister()
    shutil.rmtree(tmp, ignore_errors=True)
    print("blender bake add-on test passed")


main()
