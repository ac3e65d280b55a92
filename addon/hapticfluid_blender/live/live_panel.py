# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session's panel (3D View > Sidebar > hapticfluid).

Laid out to read whole at the sidebar's default width (about 200 px of text in Blender 3.4 to
5.x): short property labels, one stat per row as a name / value pair, and long text (status,
reports, gain reason, scheduling) wrapped to the region's width."""

import textwrap

import bpy

from ..properties import roles
from ..ui.prefs import package_problem

# Average width of a sidebar character in pixels at UI scale 1 (Blender's default font at 11 pt):
# wraps long text to the region's width.
CHAR_WIDTH_PX = 6.5
# Fraction of the width for the labels of the Live Session's object and device rows.
LABEL_FACTOR = 0.3


def wrapped_label(layout, context, text, icon="NONE"):
    """Text wrapped to the region's width, one label per line (the icon on the first)."""
    region = getattr(context, "region", None)
    scale = context.preferences.system.ui_scale if context.preferences else 1.0
    width_px = region.width if region is not None else 240
    chars = max(16, int((width_px - 30 * scale) / (CHAR_WIDTH_PX * scale)))
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, width=chars) or [""]):
        col.label(text=line, icon=icon if i == 0 else "NONE")


def narrow_label_row(layout, owner, name, text):
    """A property with its label in a narrow right-aligned column (a quarter of the width, where
    use_property_split gives 40%): object names and 'Simulated Falcon' fit in the field."""
    split = layout.split(factor=LABEL_FACTOR)
    split.use_property_split = False
    split.use_property_decorate = False  # no keyframe dot: its width goes to the field
    label = split.column()
    label.alignment = "RIGHT"
    label.label(text=text)
    split.prop(owner, name, text="")


def narrow_label_text(layout, text, value):
    """Like narrow_label_row, with a read-only value (an object holding a role)."""
    split = layout.split(factor=LABEL_FACTOR)
    label = split.column()
    label.alignment = "RIGHT"
    label.label(text=text)
    split.label(text=value)


def ms_text(value_ms):
    """'1146 ms', '12.3 ms', '0.412 ms': three significant digits up to 1 s."""
    return f"{value_ms:.0f} ms" if value_ms >= 100.0 else f"{value_ms:.3g} ms"


def stat_row(layout, name, value):
    """One stat as 'name   value': the name in the left half, the value in the right."""
    split = layout.split(factor=0.5)
    split.label(text=name)
    split.label(text=value)


class HAPTICFLUID_PT_live(bpy.types.Panel):
    bl_label = "Live Session"
    bl_idname = "HAPTICFLUID_PT_live"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "hapticfluid"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and hasattr(context.scene, "hapticfluid_live")

    def draw(self, context):
        live = context.scene.hapticfluid_live
        bake = roles.settings_of(context.scene)
        layout = self.layout
        layout.use_property_split = True
        problem = package_problem()
        if problem:
            wrapped_label(layout, context, problem, icon="ERROR")
            return
        col = layout.column()
        for name, text in (("domain", "Domain"), ("probe", "Probe"), ("source", "Source")):  # set in the Physics tab
            obj = getattr(bake, name)
            narrow_label_text(col, text, obj.name if obj is not None else "(none)")
        if bake.probe is not None:
            narrow_label_row(col, bake.probe.hapticfluid.probe_settings, "probe_shape", "Shape")
        narrow_label_row(col, live, "device", "Device")
        if live.device == "FALCON":
            narrow_label_row(col, live, "firmware_path", "Firmware")
        if live.device == "SIMULATED_FALCON":
            narrow_label_row(col, live, "hand_gesture", "Hand")
        if live.device in ("MOUSE", "TIMELINE") and bake.probe_shape == "MESH":
            wrapped_label(layout, context, "The probe follows the object's location and rotation; its scale "
                                           "stays as at Start (see the Device tooltip)", icon="INFO")
        row = layout.row(align=True)
        row.scale_y = 1.3
        if live.is_running:
            row.operator("hapticfluid.live_stop", icon="PAUSE")
            row.operator("hapticfluid.live_record", icon="REC", depress=live.is_recording,
                         text=record_text(context.scene) if live.is_recording else "Record")
        else:
            row.operator("hapticfluid.live_start", icon="PLAY")
        if live.status:
            wrapped_label(layout, context, live.status)


def record_text(scene) -> str:
    """The Record button's text while recording: a take locked to the playing timeline says the
    frame it started at (a punch-in: the keys from there on are being replaced)."""
    from . import live_ops

    run = live_ops.run_for(scene)
    take = run.controller.recording if run is not None else None
    if take is not None and take.frame_locked:
        return f"Recording from {take.start_frame:g}"
    return "Recording"


class HAPTICFLUID_PT_live_settings(bpy.types.Panel):
    bl_label = "Settings"
    bl_idname = "HAPTICFLUID_PT_live_settings"
    bl_parent_id = "HAPTICFLUID_PT_live"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "hapticfluid"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        live = context.scene.hapticfluid_live
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False  # no keyframe dots: their width goes to the fields
        col = layout.column(heading="Resolution")
        col.enabled = not live.is_running
        col.prop(live, "auto_resolution", text="Auto")
        sub = col.column()
        sub.enabled = not live.auto_resolution
        sub.prop(live, "resolution", text="Cells")
        col.prop(live, "cpu_share")
        col = layout.column()
        col.enabled = not live.is_running
        col.prop(live, "auto_workspace", text="Fit Workspace")
        sub = col.column()
        sub.enabled = not live.auto_workspace
        sub.prop(live, "workspace_scale", text="Scale")
        sub.prop(live, "workspace_offset", text="Offset")
        col = layout.column()
        col.enabled = not live.is_running
        col.prop(live, "auto_force_gain", text="Derive Gain")
        sub = col.column()
        sub.enabled = not live.auto_force_gain
        sub.prop(live, "force_gain", text="Gain")
        sub.prop(live, "allow_unsafe_gain", text="Allow Unsafe Gain", icon="ERROR" if live.allow_unsafe_gain else "NONE")
        sub = col.row()
        sub.enabled = live.auto_force_gain
        sub.prop(live, "feel", expand=True)
        col.prop(live, "max_force", text="Max Force")
        col.prop(live, "bandwidth_ratio", text="Filter")
        col.prop(live, "prediction")
        if live.device in ("FALCON", "SIMULATED_FALCON"):
            col.prop(live, "feel_playback")
        col = layout.column()
        col.prop(live, "record_rate", text="Key Rate")
        col.prop(live, "density_scale", text="Density")
        col.prop(live, "show_temperature", text="Temperature")


def feel_text(hand_n, fluid_n, gain):
    """What the hand feels against what the probe feels, 3 significant digits:
    '1.15 N on the hand = 0.0462 N in the fluid x 24.9'."""
    return f"{hand_n:.3g} N on the hand = {fluid_n:.3g} N in the fluid x {gain:.3g}"


class HAPTICFLUID_PT_live_stats(bpy.types.Panel):
    bl_label = "Stats"
    bl_idname = "HAPTICFLUID_PT_live_stats"
    bl_parent_id = "HAPTICFLUID_PT_live"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "hapticfluid"

    def draw(self, context):
        live = context.scene.hapticfluid_live
        col = self.layout.column(align=True)
        stat_row(col, "Resolution", f"{live.resolution_used} cells")
        if live.device_used:
            backend, _, renderer = live.device_used.partition(": ")
            stat_row(col, "Backend", backend)
            wrapped_label(col, context, renderer)
        stat_row(col, "Simulation", f"{live.sim_rate_hz:.1f} Hz")
        stat_row(col, "Haptic", f"{live.haptic_rate_hz:.0f} Hz")
        stat_row(col, "Jitter p99", ms_text(live.jitter_p99_ms))
        stat_row(col, "Latency p50", ms_text(live.latency_p50_ms))
        stat_row(col, "Latency p99", ms_text(live.latency_p99_ms))
        stat_row(col, "Hand force", f"{live.device_force_n:.3f} N")
        stat_row(col, "Fluid force", f"{live.force_n:.4f} N")
        stat_row(col, "Gain", f"{live.force_gain_used:.3g} N/N")
        col.label(text=feel_text(live.device_force_n, live.force_n, live.force_gain_used))
        stat_row(col, "Real-time", "granted" if live.realtime else "not granted")
        if live.force_gain_reason:
            col.separator()
            wrapped_label(col, context, "Gain: " + live.force_gain_reason)
        if live.device_state:
            col.separator()
            name, _, state = live.device_state.partition(": ")
            col.label(text=name)
            if state:
                col.label(text=state)
        if live.scheduling and not live.realtime:
            col.separator()
            wrapped_label(col, context, live.scheduling)


classes = (HAPTICFLUID_PT_live, HAPTICFLUID_PT_live_settings, HAPTICFLUID_PT_live_stats)
