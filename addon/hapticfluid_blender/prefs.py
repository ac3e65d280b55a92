"""The add-on's preferences: say at once when the hapticfluid package is not importable
(enabling the add-on works without it; Bake would be the first to fail)."""

import bpy

from .ui_text import wrapped_label


def package_problem():
    """None if ``hapticfluid`` imports, else what to do (for the preferences and the panels)."""
    try:
        import hapticfluid  # noqa: F401
    except ImportError as exc:
        return (f"Install the hapticfluid package into Blender's Python (see README) or add it to PYTHONPATH "
                f"(read by Blender 4.x only with --python-use-system-env): "
                f"it is not importable ({exc})")
    return None


class HapticFluidPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    def draw(self, context):
        problem = package_problem()
        if problem:
            wrapped_label(self.layout, context, problem, icon="ERROR")
        else:
            import hapticfluid

            self.layout.label(text=f"hapticfluid {hapticfluid.__version__} is importable", icon="CHECKMARK")
