# SPDX-License-Identifier: GPL-3.0-or-later
"""The farm's bake task on a .blend: `python3 -m hapticfluid.farm bake` runs the add-on's entry
point bake_main in Blender with the job's cache folder (not the .blend's own): a first chunk
(`--until 2`), the rest continuing from its checkpoint (frames 1-2 not rewritten), and a re-queued
task that resumes the finished bake (nothing rewritten). Run by ctest (label farm): python3
blend_bake_test.py BLENDER ADDON_DIR
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

MAKE_BLEND = """
import bpy, sys
sys.path.insert(0, {addon!r})
import hapticfluid_blender
hapticfluid_blender.register()
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
domain = bpy.context.active_object
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.12, location=(0.3, 0.5, 0.55))
probe = bpy.context.active_object
probe.keyframe_insert("location", frame=1)
probe.location = (0.65, 0.5, 0.55)
probe.keyframe_insert("location", frame=3)
s = bpy.context.scene.hapticfluid_bake
s.domain, s.probe, s.probe_shape = domain, probe, "SPHERE"
s.resolution, s.frame_start, s.frame_end, s.substeps = 12, 1, 3, 1
s.cache_dir = "//the_blend_s_own_cache"
bpy.ops.wm.save_as_mainfile(filepath={blend!r})
"""


def fail(message):
    print(f"FAIL: {message}", flush=True)
    sys.exit(1)


def bake_task(root: Path, blender: str, *until: str) -> str:
    r = subprocess.run([sys.executable, "-m", "hapticfluid.farm", "bake", "--root", str(root), "--resolution", "16",
                        "--cache", "caches/shot", "--blender", blender, "shot.blend", *until],
                       capture_output=True, text=True, timeout=600)
    print(r.stdout[-4000:], r.stderr[-4000:], sep="\n", flush=True)
    if r.returncode != 0:
        fail(f"the bake task exited {r.returncode}")
    return r.stdout + r.stderr


def main(blender: str, addon: str) -> None:
    root = Path(tempfile.mkdtemp(prefix="hf_farm_blend_"))
    try:
        script = root / "make_blend.py"
        script.write_text(MAKE_BLEND.format(addon=addon, blend=str(root / "shot.blend")))
        r = subprocess.run([blender, "--background", "--factory-startup", "--python-use-system-env", "--python-exit-code", "1",
                            "--python", str(script)], capture_output=True, text=True, timeout=300)
        if r.returncode != 0 or not (root / "shot.blend").exists():
            fail(f"making the .blend failed:\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}")
        out = bake_task(root, blender, "--until", "2")  # a first chunk
        cache = root / "caches" / "shot"
        manifest = json.loads((cache / "hapticfluid_bake.json").read_text())
        if manifest["frames_done"] != [1, 2] or "bake finished: 2 frame(s)" not in out:
            fail(f"the chunk --until 2 baked frames {manifest['frames_done']}")
        first_chunk = {p.name: p.stat().st_mtime_ns for p in (cache / "data").iterdir()}
        out = bake_task(root, blender)  # the rest, from the chunk's checkpoint
        manifest = json.loads((cache / "hapticfluid_bake.json").read_text())
        if any((cache / "data" / name).stat().st_mtime_ns != t for name, t in first_chunk.items()):
            fail("the task after the chunk rewrote the chunk's frames")
        if manifest["frames_done"] != [1, 2, 3] or not manifest["complete"]:
            fail(f"frames done: {manifest['frames_done']}")
        if manifest["scene"]["resolution"] != 16:
            fail("the task's --resolution did not reach the bake")
        if (root / "the_blend_s_own_cache").exists():
            fail("the bake went to the .blend's own cache folder, not the job's")
        before = {p.name: p.stat().st_mtime_ns for p in (cache / "data").iterdir()}
        out = bake_task(root, blender)
        if "finished: 0 frame(s)" not in out:
            fail("the re-queued task did not resume the finished bake")
        if {p.name: p.stat().st_mtime_ns for p in (cache / "data").iterdir()} != before:
            fail("the re-queued task rewrote frames")
        print("ok: .blend baked by the farm task into the job's cache, a chunk --until 2 then the rest; the "
              "re-queued task resumed", flush=True)
    finally:
        shutil.rmtree(root, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
