"""The Physics tab (Properties > Physics), as Mantaflow's Fluid: a ``hapticfluid`` button among the
physics buttons gives the active object a role (a menu: Domain, Probe, Smoke Source; X removes
it), and the ``hapticfluid`` panel shows the role as buttons and its settings in sub-panels with
units: Domain (the bake's controls; Resolution, Fluid, Pressure Solver, Cache, Display), Probe
(Shape, Velocity Source), Smoke Source (Emission). Setting a role goes through the Set Role
operator, which refuses a second holder with a report naming the one that has it."""

import bpy
from bpy.props import EnumProperty

from . import panels, properties, roles


class HAPTICFLUID_OT_set_role(bpy.types.Operator):
    """Give the active object a hapticfluid role (None removes it; its settings stay on the object)"""

    bl_idname = "hapticfluid.set_role"
    bl_label = "hapticfluid Role"
    bl_options = {"REGISTER", "UNDO"}

    role: EnumProperty(name="Role", items=properties.ROLE_ITEMS, default="DOMAIN",
                       description="The role the object gets (a scene has one object per role)")

    @classmethod
    def poll(cls, context):
        return getattr(context, "object", None) is not None and hasattr(context.object, "hapticfluid")

    def execute(self, context):
        obj = context.object
        current = obj.hapticfluid
        if current.role == "DOMAIN" and self.role != "DOMAIN" and current.domain_settings.is_baking:
            self.report({"ERROR"}, f"Cancel the bake first (Esc) or wait for it: the domain '{obj.name}' is baking")
            return {"CANCELLED"}
        why = roles.conflict(obj, self.role)
        if why is not None:
            self.report({"ERROR"}, why[:1].upper() + why[1:])
            return {"CANCELLED"}
        current.role = self.role
        self.report({"INFO"}, f"'{obj.name}' is the {roles.label(self.role)}" if self.role != "NONE"
                    else f"'{obj.name}' has no hapticfluid role now")
        return {"FINISHED"}


def draw_physics_button(self, context):
    """Appended to PHYSICS_PT_add: the hapticfluid button (a role menu, or X to remove the role)."""
    obj = getattr(context, "object", None)
    if obj is None or not hasattr(obj, "hapticfluid"):
        return
    row = self.layout.row(align=True)
    if roles.role_of(obj) == "NONE":
        row.operator_menu_enum(HAPTICFLUID_OT_set_role.bl_idname, "role", text="hapticfluid", icon="MOD_FLUIDSIM")
    else:
        row.operator(HAPTICFLUID_OT_set_role.bl_idname, text="hapticfluid", icon="X").role = "NONE"


def _role_of(context):
    obj = getattr(context, "object", None)
    return roles.role_of(obj) if obj is not None and hasattr(obj, "hapticfluid") else "NONE"


class HAPTICFLUID_PT_physics(bpy.types.Panel):
    bl_label = "hapticfluid"
    bl_idname = "HAPTICFLUID_PT_physics"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return _role_of(context) != "NONE"

    def draw(self, context):
        layout = self.layout
        obj = context.object
        role = obj.hapticfluid.role
        s = roles.settings_of(context.scene)
        panels.draw_problems(layout, context, s)
        split = layout.split(factor=0.3)
        split.label(text="Type")
        row = split.row(align=True)
        for key, name, _ in properties.ROLE_ITEMS[1:]:
            row.operator(HAPTICFLUID_OT_set_role.bl_idname, text=name, depress=role == key).role = key
        if role == "DOMAIN":
            if s.domain == obj:
                panels.draw_bake(layout, context, s)
            else:  # a second domain (Shift+D): the scene's other one is baked
                panels.wrapped_label(layout, context, f"Bake from the scene's domain '{s.domain.name}'",
                                     icon="INFO")
        elif s.domain is None:
            panels.wrapped_label(layout, context, "Give a mesh the Domain role (the simulated box) to bake or run "
                                                  "a live session", icon="INFO")
        else:
            panels.wrapped_label(layout, context, f"Acts in the domain '{s.domain.name}' (bake from its Physics tab "
                                                  "or the Scene tab)", icon="INFO")


class _RolePanel:
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"
    bl_parent_id = "HAPTICFLUID_PT_physics"
    role = "NONE"

    @classmethod
    def poll(cls, context):
        return _role_of(context) == cls.role

    def _layout(self, context):
        """(a column with split labels, the object's settings group of this role)."""
        self.layout.use_property_split = True
        self.layout.use_property_decorate = False
        return self.layout.column(), roles.role_settings(context.object)


class HAPTICFLUID_PT_domain_resolution(_RolePanel, bpy.types.Panel):
    bl_label = "Resolution"
    bl_idname = "HAPTICFLUID_PT_domain_resolution"
    role = "DOMAIN"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "resolution")
        steps = col.column(heading="Time Steps")
        steps.prop(s, "adaptive_substeps", text="Adaptive")
        if s.adaptive_substeps:
            col.prop(s, "cfl")
            col.prop(s, "max_substeps")
        else:
            col.prop(s, "substeps")


class HAPTICFLUID_PT_domain_fluid(_RolePanel, bpy.types.Panel):
    bl_label = "Fluid"
    bl_idname = "HAPTICFLUID_PT_domain_fluid"
    role = "DOMAIN"

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


class HAPTICFLUID_PT_domain_solver(_RolePanel, bpy.types.Panel):
    bl_label = "Pressure Solver"
    bl_idname = "HAPTICFLUID_PT_domain_solver"
    bl_options = {"DEFAULT_CLOSED"}
    role = "DOMAIN"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "pressure_solver", text="Solver")
        col.prop(s, "pressure_iterations", text="Iterations")
        col.prop(s, "pressure_tolerance", text="Tolerance")


class HAPTICFLUID_PT_domain_cache(_RolePanel, bpy.types.Panel):
    bl_label = "Cache"
    bl_idname = "HAPTICFLUID_PT_domain_cache"
    role = "DOMAIN"

    def draw(self, context):
        col, s = self._layout(context)
        frames = col.column(align=True)  # one per line: readable at the default width
        frames.prop(s, "frame_start", text="Frame Start")
        frames.prop(s, "frame_end", text="End")
        col.prop(s, "cache_dir")
        grids = col.column(heading="Grids", align=True)
        grids.label(text="Density (always)")
        grids.prop(s, "write_velocity")
        grids.prop(s, "write_pressure")
        files = col.column(heading="Files")
        files.prop(s, "half_float")
        col.prop(s, "compression")
        col.prop(s, "tolerance")


class HAPTICFLUID_PT_domain_display(_RolePanel, bpy.types.Panel):
    bl_label = "Display"
    bl_idname = "HAPTICFLUID_PT_domain_display"
    role = "DOMAIN"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "density_scale")
        col.prop(s, "volume_object")


class HAPTICFLUID_PT_probe_shape(_RolePanel, bpy.types.Panel):
    bl_label = "Shape"
    bl_idname = "HAPTICFLUID_PT_probe_shape"
    role = "PROBE"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "probe_shape", text="Shape")


class HAPTICFLUID_PT_probe_velocity(_RolePanel, bpy.types.Panel):
    bl_label = "Velocity Source"
    bl_idname = "HAPTICFLUID_PT_probe_velocity"
    role = "PROBE"

    def draw(self, context):
        col, _s = self._layout(context)
        panels.wrapped_label(col, context, "Bake: the object's animation (its world matrix at every frame; the "
                                           "velocity is the motion between substeps, m/s)")
        live = getattr(context.scene, "hapticfluid_live", None)
        if live is not None:
            col.prop(live, "device", text="Live")


class HAPTICFLUID_PT_source_emission(_RolePanel, bpy.types.Panel):
    bl_label = "Emission"
    bl_idname = "HAPTICFLUID_PT_source_emission"
    role = "SOURCE"

    def draw(self, context):
        col, s = self._layout(context)
        col.prop(s, "source_density", text="Density")
        col.prop(s, "source_temperature", text="Temperature (K)")


classes = (HAPTICFLUID_OT_set_role, HAPTICFLUID_PT_physics, HAPTICFLUID_PT_domain_resolution,
           HAPTICFLUID_PT_domain_fluid, HAPTICFLUID_PT_domain_solver, HAPTICFLUID_PT_domain_cache,
           HAPTICFLUID_PT_domain_display, HAPTICFLUID_PT_probe_shape, HAPTICFLUID_PT_probe_velocity,
           HAPTICFLUID_PT_source_emission)


def attach():
    add = getattr(bpy.types, "PHYSICS_PT_add", None)  # Blender's own physics buttons
    if add is not None:
        add.append(draw_physics_button)


def detach():
    add = getattr(bpy.types, "PHYSICS_PT_add", None)
    if add is not None:
        add.remove(draw_physics_button)
