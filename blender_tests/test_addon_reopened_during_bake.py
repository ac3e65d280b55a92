"""Runs inside `blender --background --factory-startup --python-exit-code 1`: a .blend saved
while a bake was running (is_baking set) and opened again has its Bake/Resume/Free buttons
usable, with a status saying the bake was interrupted."""

import os
import sys
import tempfile

import bpy

SOURCE = os.environ["HAPTICFLUID_SOURCE_DIR"]
sys.path.insert(0, os.path.join(SOURCE, "addon"))

import hapticfluid_blender  # noqa: E402


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    print("ok:", message)


def main():
    hapticfluid_blender.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    settings = bpy.context.scene.hapticfluid_bake
    settings.is_baking = True  # what a file auto-saved in the middle of a bake holds
    settings.status = "baking..."
    check(not bpy.ops.hapticfluid.bake.poll(), "Bake is greyed out while is_baking is set")
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "saved_during_bake.blend")
        bpy.ops.wm.save_as_mainfile(filepath=path)
        bpy.ops.wm.open_mainfile(filepath=path)
        settings = bpy.context.scene.hapticfluid_bake
        check(not settings.is_baking, "reopening the file clears the stale is_baking")
        check("interrupted" in settings.status and "Resume" in settings.status,
              f"the status says what happened: {settings.status!r}")
        check(bpy.ops.hapticfluid.bake.poll() and bpy.ops.hapticfluid.bake_resume.poll()
              and bpy.ops.hapticfluid.bake_free.poll(), "Bake, Resume and Free are usable again")
    hapticfluid_blender.unregister()
    check(hapticfluid_blender.properties.clear_stale_bake_state not in bpy.app.handlers.load_post,
          "unregister removes the load handler")


main()
