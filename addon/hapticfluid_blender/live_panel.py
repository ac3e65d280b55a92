"""The live session's panel (3D View > Sidebar > hapticfluid)."""

import bpy

from .prefs import package_problem


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
        bake = context.scene.hapticfluid_bake
        layout = self.layout
        layout.use_property_split = True
        problem = package_problem()
        if problem:
            layout.label(text=problem, icon="ERROR")
            return
        col = layout.column()
        col.prop(bake, "domain")
        col.prop(bake, "probe")
        col.prop(bake, "probe_shape")
        col.prop(bake, "source")
        col.separator()
        col.prop(live, "device")
        if live.device == "FALCON":
            col.prop(live, "firmware_path")
        row = layout.row(align=True)
        row.scale_y = 1.3
        if live.is_running:
            row.operator("hapticfluid.live_stop", icon="PAUSE")
            row.operator("hapticfluid.live_record", icon="REC", depress=live.is_recording,
                         text="Recording" if live.is_recording else "Record")
        else:
            row.operator("hapticfluid.live_start", icon="PLAY")
        if live.status:
            layout.label(text=live.status)


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
        col = layout.column()
        col.enabled = not live.is_running
        col.prop(live, "auto_resolution")
        sub = col.column()
        sub.enabled = not live.auto_resolution
        sub.prop(live, "resolution")
        col.prop(live, "auto_workspace")
        sub = col.column()
        sub.enabled = not live.auto_workspace
        sub.prop(live, "workspace_scale")
        sub.prop(live, "workspace_offset")
        col.prop(live, "auto_force_gain")
        sub = col.column()
        sub.enabled = not live.auto_force_gain
        sub.prop(live, "force_gain")
        col.prop(live, "max_force")
        col.prop(live, "bandwidth_ratio")
        col.prop(live, "prediction")
        layout.prop(live, "record_rate")
        layout.prop(live, "density_scale")
        layout.prop(live, "show_temperature")


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
        col.label(text=f"Resolution: {live.resolution_used}")
        col.label(text=f"Simulation: {live.sim_rate_hz:.1f} Hz")
        col.label(text=f"Haptic: {live.haptic_rate_hz:.0f} Hz, jitter p99 {live.jitter_p99_ms:.3f} ms")
        col.label(text=f"Latency: p50 {live.latency_p50_ms:.1f} ms, p99 {live.latency_p99_ms:.1f} ms")
        col.label(text=f"Force: {live.force_n:.4f} N (device {live.device_force_n:.3f} N)")
        col.label(text=f"Gain: {live.force_gain_used:.3g} device N per fluid N")
        if live.force_gain_reason:
            col.label(text=live.force_gain_reason)
        if live.device_state:
            col.label(text=live.device_state)
        col.label(text="Real-time priority: " + ("granted" if live.realtime else "not granted"))
        if live.scheduling and not live.realtime:
            col.label(text=live.scheduling)


classes = (HAPTICFLUID_PT_live, HAPTICFLUID_PT_live_settings, HAPTICFLUID_PT_live_stats)
