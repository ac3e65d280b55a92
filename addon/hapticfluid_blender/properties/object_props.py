# SPDX-License-Identifier: GPL-3.0-or-later
"""The roles and their settings, stored on the objects: ``object.hapticfluid.role`` (Domain,
Probe, Smoke Source) and one settings group per role (``domain_settings`` holds the bake's
settings, its cache and status; ``probe_settings``; ``source_settings``). Read them through
``roles.settings_of(scene)``; the scene-level layout of older files is in ``legacy.py``."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from ..render import volume


ROLE_ITEMS = (
    ("NONE", "None", "No hapticfluid role"),
    ("DOMAIN", "Domain", "The simulated box (this mesh's world bounding box); holds the bake's settings and cache"),
    ("PROBE", "Probe", "The object whose motion pushes the fluid (baked from its animation, or moved live)"),
    ("SOURCE", "Smoke Source", "The object marking where smoke and heat are emitted"),
)
ROLE_LABELS = {key: name for key, name, _ in ROLE_ITEMS}


def _engine_limits():
    """The ranges the engine takes (hapticfluid.FluidSettings.limits(), the smoke source's
    MAX_SOURCE_DENSITY and MAX_SOURCE_TEMPERATURE_K), by setting; {} without the package (no bake
    can run then, and the panel says why)."""
    try:
        import hapticfluid
    except ImportError:
        return {}
    limits = hapticfluid.FluidSettings.limits()
    limits["source_density"] = {"min": 0.0, "max": hapticfluid.MAX_SOURCE_DENSITY, "max_exclusive": False}
    limits["source_temperature"] = {"min": 0.0, "max": hapticfluid.MAX_SOURCE_TEMPERATURE_K, "max_exclusive": False}
    return limits


_LIMITS = _engine_limits()


def _below(x):
    """The largest float32 below x > 0 (Blender's properties hold float32: an excluded maximum)."""
    import struct

    return struct.unpack("<f", struct.pack("<I", struct.unpack("<I", struct.pack("<f", x))[0] - 1))[0]


def _limits(setting, integer=False, **soft):
    """A property's min and max: the engine's range of ``setting``, so a field offers exactly what
    the bake takes; ``soft`` (soft_min, soft_max) only narrows the slider's range inside it."""
    r = _LIMITS.get(setting)
    if r is None:
        return soft
    hi = _below(r["max"]) if r["max_exclusive"] else r["max"]
    out = {"min": int(r["min"]) if integer else r["min"], "max": int(hi) if integer else hi}
    out.update({k: max(out["min"], min(out["max"], v)) for k, v in soft.items()})
    return out


class HapticFluidProbeSettings(bpy.types.PropertyGroup):
    """The probe's settings, on the object holding the Probe role."""

    probe_shape: EnumProperty(
        name="Probe Shape", default="MESH",
        items=(("MESH", "Mesh", "The probe object's own closed mesh (modifiers applied, at the current frame), "
                                "moved rigidly by its animation"),
               ("SPHERE", "Sphere", "A sphere of half the object's largest local extent, scaled with the object")),
        description="What the probe pushes the fluid with")


class HapticFluidSourceSettings(bpy.types.PropertyGroup):
    """The smoke source's settings, on the object holding the Smoke Source role."""

    source_density: FloatProperty(name="Source Density", default=1.0, **_limits("source_density"),
                                  description="Smoke concentration held in the emitter (dimensionless)")
    source_temperature: FloatProperty(name="Source Temperature (K)", default=8.0, **_limits("source_temperature"),
                                      description="Temperature above ambient held in the emitter (K)")


class HapticFluidDomainSettings(bpy.types.PropertyGroup):
    """The bake's settings, its cache and its status, on the object holding the Domain role."""

    resolution: IntProperty(
        name="Resolution", default=64, min=8, max=1024, soft_max=256,
        description="Cells along the domain's longest edge (bake resolution, independent of the "
                    "interactive one)")
    frame_start: IntProperty(name="Start", default=1, min=0, max=9999,
                             description="First frame to bake (the fluid is at rest one frame before)")
    frame_end: IntProperty(name="End", default=48, min=0, max=9999, description="Last frame to bake (inclusive)")
    substeps: IntProperty(name="Substeps", default=2, min=1, max=64,
                          description="Simulation steps per frame (when not adaptive)")
    adaptive_substeps: BoolProperty(
        name="Adaptive Substeps", default=False,
        description="Choose the steps per frame from the fastest velocity (CFL condition)")
    cfl: FloatProperty(name="CFL", default=1.0, min=0.1, max=10.0,
                       description="Cells the fastest flow may cross per step when adaptive")
    max_substeps: IntProperty(name="Max Substeps", default=16, min=1, max=256,
                              description="Upper limit of adaptive steps per frame")
    cache_dir: StringProperty(
        name="Cache Folder", subtype="DIR_PATH", default="//hapticfluid_cache",
        description="Folder of the bake (data/fluid_data_####.vdb, checkpoint, manifest); // is the "
                    ".blend's folder")
    write_velocity: BoolProperty(name="Velocity (m/s)", default=False,
                                 description="Also write the 'velocity' grid (cell-centred, m/s)")
    write_pressure: BoolProperty(name="Pressure (Pa)", default=False,
                                 description="Also write the 'pressure' grid (dynamic pressure, Pa)")
    half_float: BoolProperty(name="Half Floats", default=True,
                             description="Store grids as 16-bit floats (about half the disk space)")
    compression: EnumProperty(
        name="Compression", default="blosc",
        items=(("blosc", "Blosc", "Fast compression (what Blender's own fluid cache uses)"),
               ("zip", "Zip", "Smaller, slower"),
               ("none", "None", "Uncompressed")),
        description="Compression of the VDB files")
    tolerance: FloatProperty(name="Sparse Tolerance", default=1e-4, min=0.0, max=1.0, precision=5,
                             description="Values at or below this are left out of the files (sparse)")
    checkpoint_every: IntProperty(
        name="Checkpoint Every", default=10, min=0, max=9999, soft_max=100,  # hapticfluid.bake.scene.CHECKPOINT_EVERY
        description="Keep the simulation's full state every this many frames (0: only the latest), so that "
                    "after a change Resume re-bakes from the checkpoint before it instead of from the start; "
                    "each costs the size shown below on disk")
    fluid_density: FloatProperty(name="Fluid Density (kg/m³)", default=1.2, **_limits("fluid_density"), unit="NONE",
                                 description="Density of the fluid (kg/m^3): 1.2 air, 1000 water")
    open_top: BoolProperty(name="Open Top", default=True,
                           description="The domain's top is open (smoke leaves) instead of a lid")
    vorticity: FloatProperty(name="Vorticity", default=0.4, **_limits("vorticity", soft_max=100.0),
                             description="Vorticity confinement (dimensionless): curlier smoke")
    heat_buoyancy: FloatProperty(name="Heat Buoyancy (m/s²/K)", default=1.0, **_limits("heat_buoyancy", soft_min=0.0),
                                 description="Upward acceleration per kelvin above ambient (m/s^2/K)")
    smoke_dissipation: FloatProperty(name="Smoke Dissipation (1/s)", default=0.05, **_limits("smoke_dissipation"),
                                     description="Rate the smoke fades (1/s)")
    heat_dissipation: FloatProperty(name="Heat Dissipation (1/s)", default=0.4, **_limits("heat_dissipation"),
                                    description="Rate the heat fades (1/s)")
    pressure_solver: EnumProperty(
        name="Pressure Solver", default="MULTIGRID",  # the default before: versioning.CHANGED_DEFAULTS
        items=(("JACOBI", "Jacobi", "Fixed Jacobi sweeps: cheap per sweep, converges slowly"),
               ("MULTIGRID", "Multigrid", "Conjugate gradient with a multigrid V-cycle: a few iterations "
                                          "reach a small residual")),
        description="How the pressure is solved each step")
    pressure_iterations: IntProperty(name="Pressure Iterations", default=40, **_limits("pressure_iterations", True),
                                     description="Jacobi sweeps or multigrid iterations per step "
                                                 "(the cap when a tolerance is set)")
    pressure_tolerance: FloatProperty(name="Pressure Tolerance", default=1e-3, precision=6,
                                      **_limits("pressure_tolerance", soft_max=0.5),
                                      description="Stop the pressure solve at this relative residual "
                                                  "(dimensionless); 0 runs the fixed iteration count")
    density_scale: FloatProperty(name="Render Density", default=20.0, min=0.0, max=10000.0,
                                 update=lambda self, _context: volume.apply_density(self.volume_object,
                                                                                    self.density_scale),
                                 description="Density multiplier of the smoke material (Principled Volume)")
    volume_object: PointerProperty(name="Volume", type=bpy.types.Object,
                                   description="The Volume object showing the baked frames")
    # Status, written by the operators (not user settings).
    is_baking: BoolProperty(name="Baking", default=False, description="A bake is running")
    progress: FloatProperty(name="Progress", default=0.0, min=0.0, max=1.0, subtype="FACTOR",
                            description="Share of the frames baked")
    status: StringProperty(name="Status", default="", description="What the last bake did")
    baked_inputs: StringProperty(
        name="Baked Inputs", default="",
        description="What the cache was baked from (JSON of bake.cache_plan.inputs), for 'cache out of date'")
    # The domain's display before the bake turned it into a wire frame; Free restores it.
    domain_display_saved: BoolProperty(name="Domain Display Saved", default=False,
                                       description="The two properties below hold the domain's display")
    domain_display_type: StringProperty(name="Domain Display Type", default="TEXTURED",
                                        description="The domain's display type before the bake")
    domain_hide_render: BoolProperty(name="Domain Hidden in Renders", default=False,
                                     description="The domain's hide_render before the bake")


# What a change of an object's role runs, in order, as (object, new role): the role's checks
# (roles.check_new_role) and the smoke source's render visibility (source_mesh). Filled by the
# add-on's register(), so this module, which those import, imports neither of them.
ROLE_CHANGED_HOOKS = []


def _role_changed(self, context):
    for hook in ROLE_CHANGED_HOOKS:
        hook(self.id_data, self.role)


class HapticFluidObjectSettings(bpy.types.PropertyGroup):
    """An object's hapticfluid role and the settings of each role (``object.hapticfluid``); the
    settings of a role stay when the role is removed, and come back with it."""

    role: EnumProperty(name="Type", items=ROLE_ITEMS, default="NONE", update=_role_changed,
                       description="The object's hapticfluid role; a scene has at most one object per role")
    domain_settings: PointerProperty(type=HapticFluidDomainSettings, name="Domain Settings",
                                     description="The bake's settings (used while the object is the Domain)")
    probe_settings: PointerProperty(type=HapticFluidProbeSettings, name="Probe Settings",
                                    description="The probe's settings (used while the object is the Probe)")
    source_settings: PointerProperty(type=HapticFluidSourceSettings, name="Smoke Source Settings",
                                     description="The source's settings (used while the object is the Smoke Source)")


# Registration order: the groups an object's settings point to first.
classes = (HapticFluidProbeSettings, HapticFluidSourceSettings, HapticFluidDomainSettings, HapticFluidObjectSettings)

INTERRUPTED_NOTE = ("the last bake was interrupted (Blender closed or the add-on was disabled during it); Resume "
                    "continues after its last complete frame")


@bpy.app.handlers.persistent
def clear_stale_bake_state(_filepath=None):
    """load_post handler. is_baking is saved with the .blend, so a file saved (or auto-saved)
    during a bake and reopened after Blender closed or crashed would keep it set, greying out
    Bake, Resume and Free for good. No bake of a file just opened can be running in this
    Blender: clear it and say how to continue."""
    for obj in bpy.data.objects:
        if not obj.is_property_set("hapticfluid"):  # (reading it would store an empty group)
            continue
        settings = obj.hapticfluid.domain_settings
        if settings.is_baking:
            settings.is_baking = False
            settings.status = INTERRUPTED_NOTE


def ui_name(key):
    """The UI name of a setting of any role (units included), e.g. 'Fluid Density (kg/m³)'."""
    for cls in (HapticFluidDomainSettings, HapticFluidProbeSettings, HapticFluidSourceSettings):
        if key in cls.__annotations__:
            return cls.bl_rna.properties[key].name
    raise KeyError(key)


def attach():
    bpy.types.Object.hapticfluid = PointerProperty(type=HapticFluidObjectSettings)


def detach():
    del bpy.types.Object.hapticfluid
