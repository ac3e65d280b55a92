"""The bake's settings, stored on the scene as ``scene.hapticfluid_bake``."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import source_mesh, volume


def _is_mesh(_self, obj):
    return obj.type == "MESH"


class HapticFluidBakeSettings(bpy.types.PropertyGroup):
    domain: PointerProperty(
        name="Domain", type=bpy.types.Object, poll=_is_mesh,
        description="Mesh whose world-space bounding box is the simulated box (it must not be rotated)")
    probe: PointerProperty(
        name="Probe", type=bpy.types.Object,
        description="Object whose animation (matrix_world per frame) moves the probe (its mesh, or a sphere: "
                    "see Probe Shape)")
    probe_shape: EnumProperty(
        name="Probe Shape", default="MESH",
        items=(("MESH", "Mesh", "The probe object's own closed mesh (modifiers applied, at the current frame), "
                                "moved rigidly by its animation"),
               ("SPHERE", "Sphere", "A sphere of half the object's largest local extent, scaled with the object")),
        description="What the probe pushes the fluid with")
    source: PointerProperty(
        name="Smoke Source", type=bpy.types.Object, update=source_mesh.sync_render_visibility,
        description="Smoke emitter: a closed mesh emits from its volume and follows its animation (hidden from "
                    "renders while it is the source); an Empty is a sphere of its display size; none for no emitter")
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
    fluid_density: FloatProperty(name="Fluid Density (kg/m³)", default=1.2, min=1e-3, max=1e5, unit="NONE",
                                 description="Density of the fluid (kg/m^3): 1.2 air, 1000 water")
    open_top: BoolProperty(name="Open Top", default=True,
                           description="The domain's top is open (smoke leaves) instead of a lid")
    vorticity: FloatProperty(name="Vorticity", default=0.4, min=0.0, max=100.0,
                             description="Vorticity confinement (dimensionless): curlier smoke")
    heat_buoyancy: FloatProperty(name="Heat Buoyancy (m/s²/K)", default=1.0, min=0.0, max=1000.0,
                                 description="Upward acceleration per kelvin above ambient (m/s^2/K)")
    smoke_dissipation: FloatProperty(name="Smoke Dissipation (1/s)", default=0.05, min=0.0, max=1000.0,
                                     description="Rate the smoke fades (1/s)")
    heat_dissipation: FloatProperty(name="Heat Dissipation (1/s)", default=0.4, min=0.0, max=1000.0,
                                    description="Rate the heat fades (1/s)")
    source_density: FloatProperty(name="Source Density", default=1.0, min=0.0, max=1000.0,
                                  description="Smoke concentration held in the emitter")
    source_temperature: FloatProperty(name="Source Temperature (K)", default=8.0, min=0.0, max=10000.0,
                                      description="Temperature above ambient held in the emitter (K)")
    pressure_solver: EnumProperty(
        name="Pressure Solver", default="JACOBI",
        items=(("JACOBI", "Jacobi", "Fixed Jacobi sweeps: cheap per sweep, converges slowly"),
               ("MULTIGRID", "Multigrid", "Conjugate gradient with a multigrid V-cycle: a few iterations "
                                          "reach a small residual")),
        description="How the pressure is solved each step")
    pressure_iterations: IntProperty(name="Pressure Iterations", default=40, min=1, max=100000,
                                     description="Jacobi sweeps or multigrid iterations per step "
                                                 "(the cap when a tolerance is set)")
    pressure_tolerance: FloatProperty(name="Pressure Tolerance", default=0.0, min=0.0, max=0.5, precision=6,
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
        description="The settings the cache was baked from (JSON of cache_inputs), for 'cache out of date'")
    # The domain's display before the bake turned it into a wire frame; Free restores it.
    domain_display_saved: BoolProperty(name="Domain Display Saved", default=False,
                                       description="The two properties below hold the domain's display")
    domain_display_type: StringProperty(name="Domain Display Type", default="TEXTURED",
                                        description="The domain's display type before the bake")
    domain_hide_render: BoolProperty(name="Domain Hidden in Renders", default=False,
                                     description="The domain's hide_render before the bake")


@bpy.app.handlers.persistent
def clear_stale_bake_state(_filepath=None):
    """load_post handler. is_baking is saved with the .blend, so a file saved (or auto-saved)
    during a bake and reopened after Blender closed or crashed would keep it set, greying out
    Bake, Resume and Free for good. No bake of a file just opened can be running in this
    Blender: clear it and say how to continue."""
    for scene in bpy.data.scenes:
        settings = getattr(scene, "hapticfluid_bake", None)
        if settings is not None and settings.is_baking:
            settings.is_baking = False
            settings.status = ("the last bake was interrupted (Blender closed or the add-on was disabled during "
                               "it); Resume continues after its last complete frame")


# Settings the cache depends on (frame_end is not one: raising it and pressing Resume extends
# the cache). Display-only settings (density_scale) and the status are left out.
CACHE_SETTINGS = ("probe_shape", "resolution", "frame_start", "substeps", "adaptive_substeps", "cfl", "max_substeps",
                  "cache_dir", "write_velocity", "write_pressure", "half_float", "compression", "tolerance",
                  "fluid_density", "open_top", "vorticity", "heat_buoyancy", "smoke_dissipation", "heat_dissipation",
                  "source_density", "source_temperature", "pressure_solver", "pressure_iterations",
                  "pressure_tolerance")


def cache_inputs(scene, settings):
    """What the cache is made from, cheap enough for a panel's draw: the settings above (by their
    UI names), the objects' names, the domain's and the source's world placement and size (both
    read at the current frame by the bake), gravity and frame rate. The probe and the smoke source
    count by their names only: their animation is read with frame_set on every frame, too slow
    for a draw, and their placement at the current frame changes as the timeline plays."""
    out = {}
    for key in CACHE_SETTINGS:
        value = getattr(settings, key)
        out[settings.bl_rna.properties[key].name] = round(value, 9) if isinstance(value, float) else value
    for key in ("domain", "probe", "source"):
        obj = getattr(settings, key)
        name = settings.bl_rna.properties[key].name
        if obj is None or key in ("probe", "source"):  # animated: read per frame by the bake
            out[name] = None if obj is None else obj.name
            continue
        out[name] = [obj.name, [round(v, 6) for row in obj.matrix_world for v in row],
                     [round(v, 6) for v in obj.dimensions]]
    out["Gravity"] = [round(v, 6) for v in scene.gravity] if scene.use_gravity else [0.0, 0.0, 0.0]
    out["Frame Rate"] = round(scene.render.fps / scene.render.fps_base, 6)
    return out


def cache_inputs_json(scene, settings) -> str:
    import json

    return json.dumps(cache_inputs(scene, settings), sort_keys=True)


def changed_cache_inputs(scene, settings):
    """The names of the settings changed since the bake ([] if none, or no bake recorded)."""
    import json

    if not settings.baked_inputs:
        return []
    try:
        baked = json.loads(settings.baked_inputs)
    except ValueError:
        return ["(unreadable record)"]
    now = json.loads(cache_inputs_json(scene, settings))  # the same rounding and JSON types
    return sorted(k for k in set(baked) | set(now) if baked.get(k) != now.get(k))


def attach():
    bpy.types.Scene.hapticfluid_bake = PointerProperty(type=HapticFluidBakeSettings)


def detach():
    del bpy.types.Scene.hapticfluid_bake
