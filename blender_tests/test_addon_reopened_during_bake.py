# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: a .blend saved
while a bake was running (is_baking set) and opened again has its Bake/Resume/Free buttons
usable, with a status saying the bake was interrupted."""

import os
import tempfile

import bpy

from support import SOURCE_DIR as SOURCE, check, settings as settings_of

import hapticfluid_blender  # noqa: E402


def main():
    hapticfluid_blender.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    settings = settings_of()
    settings.domain = bpy.context.active_object  # the Domain role: it holds the bake's state
    settings.is_baking = True  # what a file auto-saved in the middle of a bake holds
    settings.status = "baking..."
    check(not bpy.ops.hapticfluid.bake.poll(), "Bake is greyed out while is_baking is set")
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "saved_during_bake.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        settings = settings_of()
        check(settings.domain is not None and settings.domain.name == "Cube", "the domain keeps its role")
        check(not settings.is_baking, "reopening the file clears the stale is_baking")
        check("interrupted" in settings.status and "Resume" in settings.status,
              f"the status says what happened: {settings.status!r}")
        check(bpy.ops.hapticfluid.bake.poll() and bpy.ops.hapticfluid.bake_resume.poll()
              and bpy.ops.hapticfluid.bake_free.poll(), "Bake, Resume and Free are usable again")
    hapticfluid_blender.unregister()
    check(hapticfluid_blender.properties.object_props.clear_stale_bake_state not in bpy.app.handlers.load_post,
          "unregister removes the load handler")


main()


def bake_blend_from_the_command_line():
    """bake_blend.py registers the add-on after the file loads (no load handler ran): it must
    still clear a stale is_baking, and refuse a --resolution Blender would clamp."""
    import subprocess

    bpy.ops.wm.read_factory_settings(use_empty=True)
    hapticfluid_blender.register()
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    settings = settings_of()
    settings.domain = bpy.context.active_object
    settings.frame_start, settings.frame_end, settings.substeps, settings.resolution = 1, 1, 1, 8
    settings.pressure_iterations = 2
    script = os.path.join(SOURCE, "addon", "hapticfluid_blender", "bake", "bake_blend.py")
    with tempfile.TemporaryDirectory() as tmp:
        settings.cache_dir = os.path.join(tmp, "cache")
        settings.is_baking = True  # saved in the middle of a bake
        path = os.path.join(tmp, "saved_during_bake.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        hapticfluid_blender.unregister()

        def run(*args):
            return subprocess.run([bpy.app.binary_path, "--background", "--factory-startup", "--python-use-system-env", path,
                                   "--python-exit-code", "1", "--python", script, "--", *args],
                                  capture_output=True, text=True, timeout=300)

        clamped = run("--resolution", "4")
        check(clamped.returncode == 2 and "--resolution must be between 8 and 1024, got 4" in clamped.stderr,
              f"a --resolution out of range is refused, not clamped (exit {clamped.returncode})")
        baked = run()
        check(baked.returncode == 0, f"bake_blend.py bakes a file saved during a bake: {baked.stdout[-400:]}")
        check(os.path.exists(os.path.join(tmp, "cache", "data", "fluid_data_0001.vdb")), "frame 1 was written")


bake_blend_from_the_command_line()
