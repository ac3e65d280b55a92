"""hapticfluid for Blender: bake a probe's animation into an OpenVDB smoke cache.

The add-on is a thin layer: properties describe the bake, operators turn them into a
``hapticfluid.bake`` scene on Blender's main thread and run the bake on a worker thread that
never touches ``bpy``; the result is a Volume object that Cycles renders. It needs the
``hapticfluid`` Python package (with its native module) importable from Blender's Python.
"""

bl_info = {
    "name": "hapticfluid",
    "author": "hapticfluid developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Scene > hapticfluid Bake",
    "description": "Touchable GPU smoke: bake a probe's motion to an OpenVDB volume sequence",
    "category": "Physics",
}

from . import bake_ops, farm_ops, panels, properties  # noqa: E402  (bl_info first, as Blender expects)

classes = (
    properties.HapticFluidBakeSettings,
    bake_ops.HAPTICFLUID_OT_bake,
    bake_ops.HAPTICFLUID_OT_bake_resume,
    bake_ops.HAPTICFLUID_OT_bake_free,
    panels.HAPTICFLUID_PT_bake,
    farm_ops.HAPTICFLUID_OT_write_farm_job,
)


def register():
    import bpy

    for cls in classes:
        bpy.utils.register_class(cls)
    properties.attach()
    if properties.clear_stale_bake_state not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(properties.clear_stale_bake_state)


def unregister():
    import bpy

    if properties.clear_stale_bake_state in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(properties.clear_stale_bake_state)
    properties.detach()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
