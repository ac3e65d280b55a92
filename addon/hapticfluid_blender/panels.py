"""The bake panel: Properties editor > Scene tab."""

import bpy

from . import farm_ops


class HAPTICFLUID_PT_bake(bpy.types.Panel):
    bl_label = "hapticfluid Bake"
    bl_idname = "HAPTICFLUID_PT_bake"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "scene"

    @classmethod
    def poll(cls, context):
        return context.scene is not None and hasattr(context.scene, "hapticfluid_bake")

    def draw(self, context):
        s = context.scene.hapticfluid_bake
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(s, "domain")
        col.prop(s, "probe")
        col.prop(s, "probe_shape")
        col.prop(s, "source")
        col.separator()
        col.prop(s, "resolution")
        row = col.row(align=True)
        row.prop(s, "frame_start")
        row.prop(s, "frame_end")
        col.prop(s, "adaptive_substeps")
        if s.adaptive_substeps:
            col.prop(s, "cfl")
            col.prop(s, "max_substeps")
        else:
            col.prop(s, "substeps")
        col.separator()
        col.prop(s, "fluid_density")
        col.prop(s, "open_top")
        col.prop(s, "vorticity")
        col.prop(s, "heat_buoyancy")
        col.prop(s, "smoke_dissipation")
        col.prop(s, "heat_dissipation")
        col.prop(s, "source_density")
        col.prop(s, "source_temperature")
        col.prop(s, "pressure_solver")
        col.prop(s, "pressure_iterations")
        col.prop(s, "pressure_tolerance")
        col.separator()
        col.prop(s, "cache_dir")
        row = col.row(align=True)
        row.prop(s, "write_velocity")
        row.prop(s, "write_pressure")
        col.prop(s, "half_float")
        col.prop(s, "compression")
        col.prop(s, "tolerance")
        col.prop(s, "density_scale")
        col.separator()
        row = layout.row(align=True)
        row.operator("hapticfluid.bake", icon="RENDER_ANIMATION")
        row.operator("hapticfluid.bake_resume", icon="PLAY")
        row.operator("hapticfluid.bake_free", icon="TRASH")
        if s.is_baking:
            layout.prop(s, "progress", text="Baking (Esc cancels)")
        if s.status:
            layout.label(text=s.status)
        farm_ops.draw(layout, context)
