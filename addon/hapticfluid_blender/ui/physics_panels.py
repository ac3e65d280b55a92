# SPDX-License-Identifier: GPL-3.0-or-later
"""The Physics tab (Properties > Physics), as Mantaflow's Fluid: a ``hapticfluid`` button among the
physics buttons gives the active object a role (a menu: Domain, Probe, Smoke Source; X removes
it), and the ``hapticfluid`` panel shows the role as buttons and its settings in sub-panels with
units: Domain (the bake's controls; Resolution, Fluid, Pressure Solver, Cache, Display), Probe
(Shape, Velocity Source), Smoke Source (Emission). Setting a role goes through the Set Role
operator, which refuses a second holder with a report naming the one that has it."""

import bpy
from bpy.props import EnumProperty

from . import panels
from ..properties import object_props, roles
from .ui_text import wrapped_label


class HAPTICFLUID_OT_set_role(bpy.types.Operator):
    """Give the active object a hapticfluid role (None removes it; its settings stay on the object)"""

    bl_idname = "hapticfluid.set_role"
    bl_label = "hapticfluid Role"
    bl_options = {"REGISTER", "UNDO"}

    role: EnumProperty(name="Role", items=object_props.ROLE_ITEMS, default="DOMAIN",
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
        for key, name, _ in object_props.ROLE_ITEMS[1:]:
            row.operator(HAPTICFLUID_OT_set_role.bl_idname, text=name, depress=role == key).role = key
        if role == "DOMAIN":
            if s.domain == obj:
                panels.draw_bake(layout, context, s)
            else:  # a second domain (Shift+D): the scene's other one is baked
                wrapped_label(layout, context, f"Bake from the scene's domain '{s.domain.name}'",
                                     icon="INFO")
        elif s.domain is None:
            wrapped_label(layout, context, "Give a mesh the Domain role (the simulated box) to bake or run "
                                                  "a live session", icon="INFO")
        else:
            wrapped_label(layout, context, f"Acts in the domain '{s.domain.name}' (bake from its Physics tab "
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


def _draw_resolution(col, s, _context):
    col.prop(s, "resolution")
    steps = col.column(heading="Time Steps")
    steps.prop(s, "adaptive_substeps", text="Adaptive")
    if s.adaptive_substeps:
        col.prop(s, "cfl")
        col.prop(s, "max_substeps")
    else:
        col.prop(s, "substeps")


def _draw_fluid(col, s, context):
    col.prop(s, "fluid_density")
    scene = context.scene
    col.prop(scene, "use_gravity", text="Scene Gravity")
    sub = col.column()
    sub.active = scene.use_gravity
    sub.prop(scene, "gravity", text="Gravity (m/s²)")
    for name in ("open_top", "vorticity", "heat_buoyancy", "smoke_dissipation", "heat_dissipation"):
        col.prop(s, name)


def _draw_cache(col, s, _context):
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
    col.prop(s, "checkpoint_every")
    cost = checkpoint_cost(s)
    if cost:
        col.label(text=cost, icon="DISK_DRIVE")


def checkpoint_cost(s):
    """'Checkpoints: 6.34 MB each, 4 kept' at the domain's resolution and frame range ('' without
    the package or a usable domain); ``s`` is the domain's settings group."""
    try:
        from hapticfluid import assembly
        from hapticfluid.bake.plan import checkpoint_cost as cost

        from ..bake import blender_scene

        lo, hi = blender_scene.world_box(s.id_data)
        cells = assembly.grid([hi[i] - lo[i] for i in range(3)], s.resolution).cells
    except Exception:  # no package, or a domain the bake refuses (its panel says why)
        return ""
    return "Checkpoints: " + cost(cells, s.frame_end - s.frame_start + 1, s.checkpoint_every)


def _draw_probe_velocity(col, _s, context):
    wrapped_label(col, context, "Bake: the object's animation (its world matrix at every frame; the "
                                       "velocity is the motion between substeps, m/s)")
    live = getattr(context.scene, "hapticfluid_live", None)
    if live is not None:
        col.prop(live, "device", text="Live")


# The roles' sub-panels, in registration (and so display) order:
# (bl_idname, bl_label, role, what it draws, bl_options). What it draws is either a function
# (column, the role's settings group, context) or the properties of that group to draw one per
# line, each a name or (name, text).
SUB_PANEL_TABLE = (
    ("HAPTICFLUID_PT_domain_resolution", "Resolution", "DOMAIN", _draw_resolution, set()),
    ("HAPTICFLUID_PT_domain_fluid", "Fluid", "DOMAIN", _draw_fluid, set()),
    ("HAPTICFLUID_PT_domain_solver", "Pressure Solver", "DOMAIN",
     (("pressure_solver", "Solver"), ("pressure_iterations", "Iterations"), ("pressure_tolerance", "Tolerance")),
     {"DEFAULT_CLOSED"}),
    ("HAPTICFLUID_PT_domain_cache", "Cache", "DOMAIN", _draw_cache, set()),
    ("HAPTICFLUID_PT_domain_display", "Display", "DOMAIN", ("density_scale", "volume_object"), set()),
    ("HAPTICFLUID_PT_probe_shape", "Shape", "PROBE", (("probe_shape", "Shape"),), set()),
    ("HAPTICFLUID_PT_probe_velocity", "Velocity Source", "PROBE", _draw_probe_velocity, set()),
    ("HAPTICFLUID_PT_source_emission", "Emission", "SOURCE",
     (("source_density", "Density"), ("source_temperature", "Temperature (K)")), set()),
)


def _prop_lines(props):
    """A draw function for a tuple of property names or (name, text) pairs."""
    def draw_props(col, s, _context):
        for entry in props:
            name, text = (entry, None) if isinstance(entry, str) else entry
            if text is None:
                col.prop(s, name)
            else:
                col.prop(s, name, text=text)
    return draw_props


def _sub_panel(idname, label, role, contents, options):
    draw_contents = contents if callable(contents) else _prop_lines(contents)

    def draw(self, context):
        col, s = self._layout(context)
        draw_contents(col, s, context)

    attrs = {"bl_idname": idname, "bl_label": label, "role": role, "draw": draw, "__module__": __name__,
             "__doc__": f"Physics > hapticfluid > {label} ({role.lower()} role)"}
    if options:
        attrs["bl_options"] = set(options)
    return type(idname, (_RolePanel, bpy.types.Panel), attrs)


# bl_idname -> the generated panel class.
SUB_PANELS = {row[0]: _sub_panel(*row) for row in SUB_PANEL_TABLE}

classes = (HAPTICFLUID_OT_set_role, HAPTICFLUID_PT_physics, *SUB_PANELS.values())


def attach():
    add = getattr(bpy.types, "PHYSICS_PT_add", None)  # Blender's own physics buttons
    if add is not None:
        add.append(draw_physics_button)


def detach():
    add = getattr(bpy.types, "PHYSICS_PT_add", None)
    if add is not None:
        add.remove(draw_physics_button)
