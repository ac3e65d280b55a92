# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake's panels: the domain's bake controls (shared by the Physics tab and the Scene tab),
and the Scene tab's summary (which objects hold which role, the bake buttons, the farm job). The
role's settings are in the Physics tab (physics_panels.py)."""

import bpy

from . import prefs
from ..bake import cache_plan
from ..operators import farm_ops
from ..properties import roles
from .ui_text import wrapped_label

def draw_problems(layout, context, s):
    """The missing package and a role held twice, fix first; True if any was drawn."""
    found = [p for p in (prefs.package_problem(), s.problem) if p]
    for problem in found:
        wrapped_label(layout.box(), context, problem[:1].upper() + problem[1:], icon="ERROR")
    return bool(found)


def draw_bake(layout, context, s):
    """Bake / Resume / Free, the read-only progress while baking, 'cache out of date', the status
    line; ``s`` is ``roles.settings_of(scene)`` (with a domain)."""
    row = layout.row(align=True)
    row.scale_y = 1.2
    row.operator("hapticfluid.bake", icon="RENDER_ANIMATION")
    row.operator("hapticfluid.bake_resume", icon="PLAY")
    row.operator("hapticfluid.bake_free", icon="TRASH")
    if s.is_baking:
        text = f"Baking {100 * s.progress:.0f} % (Esc cancels)"
        if hasattr(layout, "progress"):  # Blender 4.0+
            layout.progress(factor=s.progress, text=text)
        else:  # a read-only bar: the property greyed out, not a slider to drag
            bar = layout.row()
            bar.use_property_split = False
            bar.enabled = False
            bar.prop(s.domain.hapticfluid.domain_settings, "progress", text=text, slider=True)
    else:
        changed = cache_plan.changed_inputs(context.scene, s)
        if changed:
            wrapped_label(layout.box(), context,
                          "Bake again (or set them back): the cache is out of date, changed since the bake: "
                          + ", ".join(changed), icon="ERROR")
        draw_plan(layout, context)
    if s.status:
        failed = s.status.startswith(("bake failed", "bake not started"))
        wrapped_label(layout, context, s.status, icon="ERROR" if failed else "INFO")


PLAN_ICONS = {"complete": "CHECKMARK", "inputs": "ERROR", "settings": "ERROR", "damaged": "ERROR"}


def draw_plan(layout, context):
    """What Resume would do now (cache_plan.py): 'Probe keys changed from frame 80: re-bake
    80-120 from the checkpoint at 72', or that every frame is up to date; nothing after a changed
    setting (the warning above says the whole cache is out of date)."""
    entry = cache_plan.current(context.scene)
    if entry is None or not entry.text:
        return
    text = entry.text[:1].upper() + entry.text[1:]
    if entry.kind != "complete":
        text += " (Resume)"
    wrapped_label(layout, context, text, icon=PLAN_ICONS.get(entry.kind, "INFO"))


def _settings_poll(context):
    return context.scene is not None and hasattr(bpy.types.Object, "hapticfluid")


class HAPTICFLUID_PT_bake(bpy.types.Panel):
    """The Scene tab's summary: who holds which role, and the domain's bake controls."""

    bl_label = "hapticfluid"
    bl_idname = "HAPTICFLUID_PT_bake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    @classmethod
    def poll(cls, context):
        return _settings_poll(context)

    def draw(self, context):
        s = roles.settings_of(context.scene)
        layout = self.layout
        draw_problems(layout, context, s)
        col = layout.column(align=True)
        for attr, role in roles.ROLE_ATTRS.items():
            obj = getattr(s, attr)
            split = col.split(factor=0.4)
            split.label(text=roles.label(role))
            split.label(text=obj.name if obj is not None else "(none)",
                        icon="OBJECT_DATA" if obj is not None else "BLANK1")
        if s.domain is None:
            wrapped_label(layout, context, f"Give a mesh the Domain role in {roles.PHYSICS_PATH} (the role's "
                                           "settings are there): no object in this scene has it", icon="INFO")
            return
        draw_bake(layout, context, s)


class HAPTICFLUID_PT_bake_farm(bpy.types.Panel):
    bl_label = "Farm"
    bl_idname = "HAPTICFLUID_PT_bake_farm"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"
    bl_parent_id = "HAPTICFLUID_PT_bake"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context):
        return _settings_poll(context)

    def draw(self, context):
        farm_ops.draw(self.layout, context)


classes = (HAPTICFLUID_PT_bake, HAPTICFLUID_PT_bake_farm)
