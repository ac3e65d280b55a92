# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: Write Farm Job
exports the scene and writes the OpenJD and Flamenco job files with every path relative to the
shared root; the exported scene bakes; no shared root, or a cache outside it, is refused with a
report that starts with the fix and writes nothing."""

import json
import os
import re
import shutil
import tempfile

import bpy

from support import empty_file, check, cube, key_locations, set_roles, settings, uv_sphere

import hapticfluid_blender  # noqa: E402


def build_scene(cache_dir):
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5))
    probe = uv_sphere(0.12, (0.3, 0.5, 0.55))
    key_locations(probe, ((1, (0.3, 0.5, 0.55)), (4, (0.65, 0.5, 0.55))))
    s = set_roles(scene, domain, probe)
    s.probe_shape = "SPHERE"
    s.resolution, s.frame_start, s.frame_end, s.substeps = 16, 1, 4, 1
    s.cache_dir = cache_dir
    return scene


def refused(expected_start):
    try:
        bpy.ops.hapticfluid.write_farm_job()
    except RuntimeError as exc:  # an ERROR report raises in background mode
        message = str(exc).split("Error: ", 1)[-1].strip()
        check(message.startswith(expected_start), f"refused, fix first: {message!r}")
        return
    raise AssertionError(f"Write Farm Job did not refuse (expected '{expected_start}...')")


def main():
    hapticfluid_blender.register()
    tmp = tempfile.mkdtemp(prefix="hf_blender_farm_")
    try:
        root = os.path.join(tmp, "shared")
        os.makedirs(root)
        scene = build_scene(os.path.join(root, "caches", "shot"))
        farm = scene.hapticfluid_farm
        farm.job_dir = os.path.join(root, "jobs", "shot")
        farm.output_dir = os.path.join(root, "renders", "shot")
        farm.chunk_size, farm.job_kind = 3, "BOTH"

        refused("Set the Shared Root")  # empty by default
        farm.shared_root = root
        settings(scene).cache_dir = os.path.join(tmp, "local_cache")
        refused("Choose a Cache Folder under the shared root")
        check(not os.path.exists(farm.job_dir), "nothing written when refused")

        settings(scene).cache_dir = os.path.join(root, "caches", "shot")
        result = bpy.ops.hapticfluid.write_farm_job()
        check(result == {"FINISHED"}, f"Write Farm Job finished ({result})")
        job = farm.job_dir
        check(os.path.isdir(os.path.join(root, "caches", "shot")) and os.path.isdir(farm.output_dir),
              "the cache and output folders are made on the shared storage")
        names = sorted(os.listdir(job))
        check(names == ["flamenco_job.json", "hapticfluid-bake-render.js", "hapticfluid_scene.json",
                        "parameter_values.json", "parameters.json", "template.yaml"], f"job files: {names}")

        with open(os.path.join(job, "parameters.json"), encoding="utf-8") as f:
            values = json.load(f)
        check(values == {"SceneFile": "jobs/shot/hapticfluid_scene.json", "CacheDir": "caches/shot",
                         "OutputDir": "renders/shot", "Resolution": 16, "Frames": "1-4", "ChunkSize": 3},
              f"OpenJD values relative to the shared root: {values}")
        with open(os.path.join(job, "flamenco_job.json"), encoding="utf-8") as f:
            flamenco = json.load(f)["settings"]
        check((flamenco["shared_root"], flamenco["scene_file"], flamenco["cache_dir"], flamenco["output_dir"])
              == (root, "jobs/shot/hapticfluid_scene.json", "caches/shot", "renders/shot"),
              f"Flamenco settings relative to the shared root: {flamenco}")
        check(farm.submit_command.startswith(f"cd {root} && openjd run jobs/shot/template.yaml -p file://jobs/shot/parameters.json"),
              f"the submit command is shown: {farm.submit_command}")

        with open(os.path.join(job, "hapticfluid_scene.json"), encoding="utf-8") as f:
            exported = json.load(f)
        check(exported["cache"]["directory"] == os.path.join("..", "..", "caches", "shot"),
              f"the exported scene's cache is relative to its folder: {exported['cache']['directory']}")
        check([k["frame"] for k in exported["probe"]["keys"]] == [0, 1, 2, 3, 4], "probe keys from frame 0 to 4")

        farm.bake_chunk_size = 2  # a chained bake: Bake 1-2, Render 1-2, Bake 3-4, Render 3-4
        check(bpy.ops.hapticfluid.write_farm_job() == {"FINISHED"}, "Write Farm Job with a bake chunk finished")
        with open(os.path.join(job, "template.yaml"), encoding="utf-8") as f:
            steps = re.findall(r'^  - name: "([^"]+)"', f.read(), flags=re.M)
        check(steps == ["Bake 1-2", "Render 1-2", "Bake 3-4", "Render 3-4"], f"chained OpenJD steps: {steps}")
        with open(os.path.join(job, "flamenco_job.json"), encoding="utf-8") as f:
            check(json.load(f)["settings"]["bake_chunk_size"] == 2, "the Flamenco job gets the bake chunk size")
        farm.bake_chunk_size = 0

        from hapticfluid.bake import bake, list_frames, load_scene

        baked = load_scene(os.path.join(job, "hapticfluid_scene.json"))
        check(os.path.normpath(baked.cache_dir) == os.path.join(root, "caches", "shot"),
              f"the exported scene's cache resolves under the shared root: {baked.cache_dir}")
        bake(baked)
        check(list_frames(os.path.join(root, "caches", "shot")) == [1, 2, 3, 4], "the exported scene bakes 4 frames")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        hapticfluid_blender.unregister()
    check(not hasattr(bpy.types.Scene, "hapticfluid_farm"), "unregister removes the farm settings")


main()
