# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender scene -> hapticfluid.bake scene, on the main thread (the only place bpy is read).

The probe's matrix_world is sampled at every frame from start - 1 to end (frame_set on each),
before any bake thread starts; the scene's current frame is restored afterwards.
"""

import os

import bpy

from ..properties.machine import backend_choice
from . import source_mesh


class SceneError(Exception):
    """The Blender scene cannot be baked; the message says what to change."""


# Where an unsaved .blend's relative cache goes (as Mantaflow does): Blender's session
# temporary folder, deleted when Blender quits.
UNSAVED_CACHE_NOTE = ("the .blend is not saved: baking into the temporary folder {folder} (deleted when Blender "
                      "quits) until you save the .blend")


def cache_folder(settings) -> str:
    path = settings.cache_dir
    if not path:
        raise SceneError("set a cache folder (Cache sub-panel): it is empty")
    if path.startswith("//") and not bpy.data.filepath:
        return os.path.normpath(os.path.join(bpy.app.tempdir, path[2:] or "hapticfluid_cache"))
    return os.path.normpath(bpy.path.abspath(path))


def cache_note(settings) -> str:
    """'' or what the artist should know about where the cache goes (an unsaved .blend)."""
    if settings.cache_dir.startswith("//") and not bpy.data.filepath:
        return UNSAVED_CACHE_NOTE.format(folder=cache_folder(settings))
    return ""


def world_box(obj):
    """The object's world-space bounding box (lo, hi), m."""
    corners = [obj.matrix_world @ _vec(c) for c in obj.bound_box]
    lo = [min(c[i] for c in corners) for i in range(3)]
    hi = [max(c[i] for c in corners) for i in range(3)]
    return lo, hi


def _vec(c):
    from mathutils import Vector

    return Vector((c[0], c[1], c[2]))


def _turn(matrix):
    """(is a box turn, angle in degrees): the rotation part is a signed permutation (90-degree
    turns and mirrors map an axis-aligned box onto an axis-aligned box), else the angle away
    from the nearest axis."""
    import math

    m = matrix.to_3x3().normalized()
    worst = 0.0
    for j in range(3):
        column = [abs(m[i][j]) for i in range(3)]
        worst = max(worst, math.degrees(math.acos(min(1.0, max(column)))))
    return worst < 1e-3, worst


def _box_mesh_problem(obj):
    """None if the object's evaluated mesh is an axis-aligned box in its own frame (every face
    normal along an axis, every vertex on the bounding box's surface), else what is wrong."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        if not mesh.polygons:
            return "it has no faces"
        lo = [min(c[i] for c in obj.bound_box) for i in range(3)]
        hi = [max(c[i] for c in obj.bound_box) for i in range(3)]
        eps = [1e-5 * max(1e-9, hi[i] - lo[i]) + 1e-7 for i in range(3)]
        for poly in mesh.polygons:
            if max(abs(c) for c in poly.normal) < 1.0 - 1e-5:
                return f"face {poly.index} is not axis-aligned (normal {tuple(round(c, 3) for c in poly.normal)})"
        for v in mesh.vertices:
            if not any(abs(v.co[i] - lo[i]) <= eps[i] or abs(v.co[i] - hi[i]) <= eps[i] for i in range(3)):
                return f"vertex {v.index} lies inside its bounding box"
    finally:
        evaluated.to_mesh_clear()
    return None


def _local_radius(obj) -> float:
    return 0.5 * max(max(c[i] for c in obj.bound_box) - min(c[i] for c in obj.bound_box) for i in range(3))


def _mesh_arrays(obj):
    """The object's evaluated mesh (modifiers applied) in its local frame: vertices and triangles."""
    vertices, triangles, flat = source_mesh.evaluated_mesh(obj)
    if flat is not None:
        raise SceneError(f"give the probe '{obj.name}' a closed mesh with thickness (e.g. a Solidify modifier) or use "
                         f"the Sphere shape: the probe mesh has no volume, it {flat}")
    return {"vertices": vertices, "triangles": triangles}


def domain_box(settings):
    """The domain's world box (lo, hi), m, after the checks the bake and the live session share."""
    if settings.problem:  # settings: roles.settings_of(scene); a role held twice (Shift+D copies it)
        raise SceneError(settings.problem)
    if settings.domain is None:
        raise SceneError("give a mesh the Domain role (Properties > Physics > hapticfluid): its bounding box is the "
                         "simulated box, and no object in the scene has that role")
    domain = settings.domain
    is_box_turn, angle = _turn(domain.matrix_world)
    if not is_box_turn:  # a box turned by anything but 90 degrees has a larger world box than itself
        raise SceneError(f"clear the rotation of the domain '{domain.name}' (Alt+R) and scale it instead: it is "
                         f"turned {angle:.3g} degrees off the world axes, and the simulated box is axis-aligned "
                         "(90-degree turns and mirrors are accepted)")
    problem = _box_mesh_problem(domain)
    if problem:  # e.g. a rotation applied with Ctrl+A: the mesh itself is turned
        raise SceneError(f"make the domain '{domain.name}' an axis-aligned box (e.g. a new cube scaled to size, "
                         f"or Clear Rotation before applying): its mesh is not a box along its axes ({problem}), "
                         "and only its bounding box would be simulated")
    return world_box(settings.domain)


def fluid_dict(scene, settings):
    """The fluid settings, named as hapticfluid.Simulation's keyword arguments."""
    return {
        "fluid_density": settings.fluid_density,
        "gravity": list(scene.gravity) if scene.use_gravity else [0.0, 0.0, 0.0],
        "open_top": settings.open_top,
        "vorticity": settings.vorticity,
        "heat_buoyancy": settings.heat_buoyancy,
        "smoke_dissipation": settings.smoke_dissipation,
        "heat_dissipation": settings.heat_dissipation,
        "pressure_iterations": settings.pressure_iterations,
        "pressure_solver": settings.pressure_solver.lower(),
        "pressure_tolerance": settings.pressure_tolerance,
    }


def source_dict(settings):
    """The smoke emitter at the current frame, or None: a mesh object's volume (source_mesh), or
    a sphere (centre, radius in m) for an Empty; with density and temperature."""
    try:
        return source_mesh.source_dict(settings)
    except source_mesh.SourceError as exc:
        raise SceneError(str(exc)) from None


def probe_shape_dict(probe, shape):
    """The probe's shape in its local frame: {"shape": "mesh", vertices, triangles} or a sphere."""
    if shape == "MESH":
        if probe.type != "MESH":
            raise SceneError(f"choose a mesh object as the probe, or the Sphere shape: the probe '{probe.name}' is not a "
                             "mesh")
        return {"shape": "mesh", **_mesh_arrays(probe)}
    return {"shape": "sphere", "radius": _local_radius(probe) if probe.type == "MESH" else probe.empty_display_size}


def settings_dict(scene, settings):
    """The scene dict's entries read from the settings alone (no object, no frame_set: cheap
    enough for a panel's draw): resolution, fluid, frames, substeps, cfl, max_substeps and the
    cache's grids and format (its folder: scene_dict)."""
    return {
        "resolution": settings.resolution,
        "fluid": fluid_dict(scene, settings),
        "frames": {"start": settings.frame_start, "end": settings.frame_end,
                   "fps": scene.render.fps / scene.render.fps_base},
        "substeps": "adaptive" if settings.adaptive_substeps else settings.substeps,
        "cfl": settings.cfl,
        "max_substeps": settings.max_substeps,
        "cache": {
            "grids": ["density"] + (["velocity"] if settings.write_velocity else [])
                     + (["pressure"] if settings.write_pressure else []),
            "compression": settings.compression,
            "half_float": settings.half_float,
            "tolerance": settings.tolerance,
            "checkpoint_every": settings.checkpoint_every,
        },
    }


def scene_dict(scene, settings):
    """The hapticfluid.bake scene dict (JSON form) for the current Blender scene and settings."""
    lo, hi = domain_box(settings)
    if settings.frame_end < settings.frame_start:
        raise SceneError(f"the end frame ({settings.frame_end}) is before the start frame ({settings.frame_start})")
    data = {"domain": {"origin": lo, "size": [hi[i] - lo[i] for i in range(3)]}, **settings_dict(scene, settings)}
    data["cache"]["directory"] = cache_folder(settings)
    data["backend"] = backend_choice(bpy.context)  # the machine's choice: shapes no frame (CACHE_INPUTS)
    source = source_dict(settings)
    moving = [obj for obj in (settings.probe, settings.source if source and "matrix" in source else None) if obj]
    keys = _sample_keys(scene, moving, settings.frame_start - 1, settings.frame_end)
    if source is not None:
        if "matrix" in source:  # a mesh source moves with its animation, as the probe does
            del source["matrix"]
            source["keys"] = keys[settings.source.name]
        data["source"] = source
    if settings.probe is not None:
        probe = settings.probe
        shape = probe_shape_dict(probe, settings.probe_shape)
        probe_keys = keys[probe.name]
        if shape["shape"] == "sphere":
            _check_sphere_fits(probe, shape["radius"], probe_keys, lo, hi, settings.resolution)
        data["probe"] = {**shape, "keys": probe_keys}
    return data


def _sample_keys(scene, objects, first, last):
    """{object name: [{"frame", "matrix"}, ...]}: each object's matrix_world at every frame from
    first to last, in one pass of frame_set; the current frame is restored afterwards."""
    keys = {obj.name: [] for obj in objects}
    if not objects:
        return keys
    current = scene.frame_current
    try:
        for frame in range(first, last + 1):
            scene.frame_set(frame)
            for obj in objects:
                keys[obj.name].append({"frame": frame, "matrix": [list(row) for row in obj.matrix_world]})
    finally:
        scene.frame_set(current)
    return keys


def _check_sphere_fits(probe, local_radius, keys, lo, hi, resolution):
    """A sphere probe that cannot fit the domain anywhere (an Empty's Size is 1 m by default) is
    refused here with what sets its size: the engine's check of the sphere at the domain's centre
    (hapticfluid.check_sphere_probe; the bake checks it at every key)."""
    import hapticfluid as hf
    from hapticfluid import assembly
    from mathutils import Matrix

    scale = max(max(abs(s) for s in Matrix(k["matrix"]).to_scale()) for k in keys)
    radius = local_radius * scale
    size = [hi[i] - lo[i] for i in range(3)]
    try:
        hf.check_sphere_probe(assembly.fluid_settings(lo, size, resolution),
                              tuple(lo[i] + 0.5 * size[i] for i in range(3)), radius)
    except hf.InvalidArgumentError as exc:
        what = (f"the Empty's Size ({probe.empty_display_size:.4g}) x its scale ({scale:.4g})" if probe.type == "EMPTY"
                else f"half its largest local extent x its scale ({scale:.4g})")
        raise SceneError(f"resize the sphere probe '{probe.name}' (its Size or scale): its radius {radius:.4g} m "
                         f"({what}) does not fit the domain at resolution {resolution}: {exc}") from None
