# SPDX-License-Identifier: GPL-3.0-or-later
"""hapticfluid for Blender: touch the smoke live (3D View > Sidebar > hapticfluid) and bake a
probe's animation into an OpenVDB smoke cache.

Objects get their roles (Domain, Probe, Smoke Source) in Properties > Physics > hapticfluid, as
with Mantaflow. The add-on is a thin layer: properties describe the bake, operators turn them into a
``hapticfluid.bake`` scene on Blender's main thread and run the bake on a worker thread that
never touches ``bpy``; the result is a Volume object that Cycles renders. It needs the
``hapticfluid`` Python package (with its native module) importable from Blender's Python.

Its command lines (a farm job's tasks, a bake without the UI) call two functions of this package
and nothing else of the add-on, so its files can move without breaking a job:

    blender --background scene.blend --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid_blender as a; a.bake_main()" -- [bake_blend.py's arguments]
    blender --background --factory-startup --python-use-system-env --python-exit-code 1 \
        --python-expr "import hapticfluid_blender as a; a.render_main()" -- [farm_render.py's arguments]
"""

bl_info = {
    "name": "hapticfluid",
    "author": "hapticfluid developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Physics > hapticfluid (roles); Properties > Scene > hapticfluid; "
                "3D View > Sidebar > hapticfluid",
    "description": "Touchable GPU smoke: bake a probe's motion to an OpenVDB volume sequence",
    "category": "Physics",
}

from bpy.app.handlers import persistent  # noqa: E402  (bl_info first)

from .bake import cache_plan, source_mesh  # noqa: E402
from .live import live_ops, live_panel, live_props  # noqa: E402
from .operators import bake_ops, farm_ops  # noqa: E402
from .properties import legacy, object_props, roles, versioning  # noqa: E402
from .ui import cache_bar, panels, physics_panels, prefs  # noqa: E402

classes = (
    *object_props.classes,
    legacy.HapticFluidBakeSettings,
    bake_ops.HAPTICFLUID_OT_bake,
    bake_ops.HAPTICFLUID_OT_bake_resume,
    bake_ops.HAPTICFLUID_OT_bake_free,
    *panels.classes,
    *physics_panels.classes,
    prefs.HapticFluidPreferences,
    farm_ops.HAPTICFLUID_OT_write_farm_job,
    live_props.HapticFluidLiveSettings,
    *live_ops.classes,
    *live_panel.classes,
)


@persistent
def _migrate_file(_filepath=None):
    """An older file's settings brought up to date, on load and when the add-on is enabled: the
    scene-level settings onto the objects (legacy), then the changed defaults kept on every domain,
    those legacy just made included (versioning)."""
    legacy.migrate()
    versioning.migrate()


# in order: a migrated is_baking is cleared next
_LOAD_HANDLERS = (_migrate_file, object_props.clear_stale_bake_state, live_props.clear_stale_live_state)


def register():
    import logging

    import bpy

    for cls in classes:
        bpy.utils.register_class(cls)
    # a role change: its checks first (they may take the role back), then the source's visibility
    object_props.ROLE_CHANGED_HOOKS[:] = [roles.check_new_role, versioning.stamp, source_mesh.sync_render_visibility]
    object_props.attach()
    legacy.attach()
    live_props.attach()
    physics_panels.attach()
    cache_bar.attach()
    cache_plan.attach()
    for handler in _LOAD_HANDLERS:
        if handler not in bpy.app.handlers.load_post:
            bpy.app.handlers.load_post.append(handler)
    try:  # a file opened while the add-on was disabled: bring its settings up to date
        _migrate_file()
        object_props.clear_stale_bake_state()  # re-enabled after a bake was cut short: none runs now
    except AttributeError:  # bpy.data is not readable while Blender starts; load_post clears it then
        pass
    live_ops.register()
    problem = prefs.package_problem()
    if problem:  # also shown in the add-on's preferences and the panels
        logging.getLogger(__name__).warning("hapticfluid: %s", problem)


def unregister():
    import bpy

    live_ops.unregister()  # ends running live sessions and removes their draw handlers first
    bake_ops.shutdown()  # cancels and joins running bakes, shows what finished
    for handler in _LOAD_HANDLERS:
        if handler in bpy.app.handlers.load_post:
            bpy.app.handlers.load_post.remove(handler)
    cache_plan.detach()
    cache_bar.detach()
    physics_panels.detach()
    live_props.detach()
    legacy.detach()
    object_props.detach()
    object_props.ROLE_CHANGED_HOOKS.clear()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)


def _arguments(argv):
    """A command line's arguments: ``argv``, or Blender's own after "--"."""
    import sys

    if argv is not None:
        return list(argv)
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def bake_main(argv=None):
    """Bake the open .blend's hapticfluid settings without the UI (bake/bake_blend.py: the
    arguments), registering the add-on first unless it is; exits non-zero when the bake fails
    (1) or an argument is bad (2)."""
    import sys

    import bpy

    from .bake import bake_blend

    if not hasattr(bpy.types.Object, "hapticfluid"):
        # registered after the .blend loaded, so its load handlers did not run: register() itself
        # moves an older file's scene settings onto the objects and clears a stale is_baking
        register()
    code = bake_blend.main(_arguments(argv))
    if code:
        sys.exit(code)


def render_main(argv=None):
    """Render a chunk of a farm job's baked frames (render/farm_render.py: the arguments); needs no
    registration. Exits non-zero when a frame is not baked or an argument is bad."""
    from .render import farm_render

    farm_render.main(_arguments(argv))
