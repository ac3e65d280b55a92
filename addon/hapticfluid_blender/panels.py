"""The bake panel (Properties editor > Scene tab) and its sub-panels, by topic, with units."""

import textwrap

import bpy

from . import farm_ops, prefs, properties

CHAR_WIDTH_PX = 7  # about one character of the UI font at scale 1, for wrapping long text


def wrapped_label(layout, context, text, icon="NONE"):
    """``text`` as several labels that fit the region's width (Blender's labels do not wrap)."""
    region = getattr(context, "region", None)
    width_px = region.width if region is not None and region.width > 1 else 400
    scale = context.preferences.system.ui_scale if context.preferences else 1.0
    scale = scale if scale > 0.0 else 1.0  # 0 in background mode
    chars = max(24, int(width_px / (CHAR_WIDTH_PX * scale)) - 6)
    col = layout.column(align=True)
    for i, line in enumerate(textwrap.wrap(text, chars) or [""]):
        col.label(text=line, icon=icon if i == 0 else ("BLANK1" if icon != "NONE" else "NONE"))
    return col


def _settings_poll(context):
    return context.scene is not None and hasattr(context.scene, "hapticfluid_bake")


class HAPTICFLUID_PT_bake(bpy.types.Panel):
    bl_label = "hapticfluid Bake"
    bl_idname = "HAPTICFLUID_PT_bake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    @classmethod
    def poll(cls, context):
        return _settings_poll(context)

    def draw(self, context):
        s = context.scene.hapticfluid_bake
        layout = self.layout
        problem = prefs.package_problem()
        if problem:
            wrapped_label(layout.box(), context, problem, icon="ERROR")
        layout.use_property_split = True
        col = layout.column()
        col.prop(s, "domain")
        col.prop(s, "probe")
        col.prop(s, "probe_shape")
        col.prop(s, "source")
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
                bar.prop(s, "progress", text=text, slider=True)
        else:
            changed = properties.changed_cache_inputs(context.scene, s)
            if changed:
                wrapped_label(layout.box(), context,
                              "Bake again (or set them back): the cache is out of date, changed since the bake: "
                              + ", ".join(changed), icon="ERROR")
        if s.status:
            failed = s.status.startswith(("bake failed", "bake not started"))
            wrapped_label(layout, context, s.status, icon="ERROR" if failed else "INFO")


class _SubPanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"
    bl_parent_id = "HAPTICFLUID_PT_bake"

    @classmethod
    def poll(cls, context):
        return _settings_poll(context)

    def _layout(self, context):
        self.layout.use_property_split = True
        self.layout.use_property_decorate = False
        return self.layout.column(), context.scene.hapticfluid_bake


class HAPTICFLUID_PT_bake_simulation(_SubPanel, bpy.types.Panel):
    bl_label = "Simulation"
    bl_idname = "HAPTICFLUID_PT_bake_simulation"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "resolution")
        frames = col.column(align=True)  # one per line: readable at the default width
        frames.prop(s, "frame_start", text="Frame Start")
        frames.prop(s, "frame_end", text="End")
        col.prop(s, "adaptive_substeps")
        if s.adaptive_substeps:
            col.prop(s, "cfl")
            col.prop(s, "max_substeps")
        else:
            col.prop(s, "substeps")


class HAPTICFLUID_PT_bake_fluid(_SubPanel, bpy.types.Panel):
    bl_label = "Fluid"
    bl_idname = "HAPTICFLUID_PT_bake_fluid"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "fluid_density")
        scene = context.scene
        col.prop(scene, "use_gravity", text="Scene Gravity")
        sub = col.column()
        sub.active = scene.use_gravity
        sub.prop(scene, "gravity", text="Gravity (m/s²)")
        col.prop(s, "open_top")
        col.prop(s, "vorticity")
        col.prop(s, "heat_buoyancy")
        col.prop(s, "smoke_dissipation")
        col.prop(s, "heat_dissipation")


class HAPTICFLUID_PT_bake_source(_SubPanel, bpy.types.Panel):
    bl_label = "Smoke Source"
    bl_idname = "HAPTICFLUID_PT_bake_source"

    def draw(self, context):
        col, s = self._layout(context)
        col.active = s.source is not None
        col.prop(s, "source_density")
        col.prop(s, "source_temperature")


class HAPTICFLUID_PT_bake_pressure(_SubPanel, bpy.types.Panel):
    bl_label = "Pressure Solver"
    bl_idname = "HAPTICFLUID_PT_bake_pressure"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "pressure_solver", text="Solver")
        col.prop(s, "pressure_iterations", text="Iterations")
        col.prop(s, "pressure_tolerance", text="Tolerance")


class HAPTICFLUID_PT_bake_cache(_SubPanel, bpy.types.Panel):
    bl_label = "Cache"
    bl_idname = "HAPTICFLUID_PT_bake_cache"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "cache_dir")
        grids = col.column(heading="Grids", align=True)
        grids.label(text="Density (always)")
        grids.prop(s, "write_velocity")
        grids.prop(s, "write_pressure")
        files = col.column(heading="Files")
        files.prop(s, "half_float")
        col.prop(s, "compression")
        col.prop(s, "tolerance")


class HAPTICFLUID_PT_bake_display(_SubPanel, bpy.types.Panel):
    bl_label = "Display"
    bl_idname = "HAPTICFLUID_PT_bake_display"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "density_scale")
        col.prop(s, "volume_object")


class HAPTICFLUID_PT_bake_farm(_SubPanel, bpy.types.Panel):
    bl_label = "Farm"
    bl_idname = "HAPTICFLUID_PT_bake_farm"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        farm_ops.draw(self.layout, context)


classes = (HAPTICFLUID_PT_bake, HAPTICFLUID_PT_bake_simulation, HAPTICFLUID_PT_bake_fluid, HAPTICFLUID_PT_bake_source,
           HAPTICFLUID_PT_bake_pressure, HAPTICFLUID_PT_bake_cache, HAPTICFLUID_PT_bake_display,
           HAPTICFLUID_PT_bake_farm)
