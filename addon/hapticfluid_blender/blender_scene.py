"""Blender scene -> hapticfluid.bake scene, on the main thread (the only place bpy is read).

The probe's matrix_world is sampled at every frame from start - 1 to end (frame_set on each),
before any bake thread starts; the scene's current frame is restored afterwards.
"""

import os

import bpy


class SceneError(Exception):
    """The Blender scene cannot be baked; the message says what to change."""


def cache_folder(settings) -> str:
    path = settings.cache_dir
    if not path:
        raise SceneError("set a cache folder")
    if path.startswith("//") and not bpy.data.filepath:
        raise SceneError(f"the cache folder '{path}' is relative to the .blend: save the .blend first or "
                         "choose an absolute folder")
    return os.path.normpath(bpy.path.abspath(path))


def world_box(obj):
    """The object's world-space bounding box (lo, hi), m."""
    corners = [obj.matrix_world @ _vec(c) for c in obj.bound_box]
    lo = [min(c[i] for c in corners) for i in range(3)]
    hi = [max(c[i] for c in corners) for i in range(3)]
    return lo, hi


def _vec(c):
    from mathutils import Vector

    return Vector((c[0], c[1], c[2]))


def _is_axis_aligned(matrix) -> bool:
    m = matrix.to_3x3().normalized()
    return all(abs(m[i][j]) < 1e-5 for i in range(3) for j in range(3) if i != j) and all(
        m[i][i] > 0 for i in range(3))


def _local_radius(obj) -> float:
    return 0.5 * max(max(c[i] for c in obj.bound_box) - min(c[i] for c in obj.bound_box) for i in range(3))


def _mesh_arrays(obj):
    """The object's evaluated mesh (modifiers applied) in its local frame: vertices and triangles."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        vertices = [list(v.co) for v in mesh.vertices]
        triangles = [list(t.vertices) for t in mesh.loop_triangles]
    finally:
        evaluated.to_mesh_clear()
    if not triangles:
        raise SceneError(f"the probe '{obj.name}' has no faces: give it a closed mesh or use the Sphere shape")
    return {"vertices": vertices, "triangles": triangles}


def domain_box(settings):
    """The domain's world box (lo, hi), m, after the checks the bake and the live session share."""
    if settings.domain is None:
        raise SceneError("choose a domain object (its bounding box is the simulated box)")
    if settings.domain.matrix_world.to_3x3().determinant() < 0.0:
        raise SceneError(f"apply or clear the negative scale of the domain '{settings.domain.name}' (Ctrl+A > Scale): "
                         "it is mirrored, and the simulated box is axis-aligned and unmirrored")
    if not _is_axis_aligned(settings.domain.matrix_world):
        raise SceneError(f"the domain '{settings.domain.name}' is rotated: the simulated box is axis-aligned, "
                         "clear its rotation (Alt+R) and scale it instead")
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
    """The smoke emitter (centre, radius in m, density, temperature) or None."""
    if settings.source is None:
        return None
    src = settings.source
    data = {"centre": list(src.matrix_world.translation), "radius": 0.5 * max(src.dimensions),
            "density": settings.source_density, "temperature": settings.source_temperature}
    if data["radius"] <= 0.0:  # an empty: use its display size
        data["radius"] = src.empty_display_size * max(src.matrix_world.to_scale())
    return data


def probe_shape_dict(probe, shape):
    """The probe's shape in its local frame: {"shape": "mesh", vertices, triangles} or a sphere."""
    if shape == "MESH":
        if probe.type != "MESH":
            raise SceneError(f"choose a mesh object as the probe, or the Sphere shape: the probe '{probe.name}' is not a "
                             "mesh")
        return {"shape": "mesh", **_mesh_arrays(probe)}
    return {"shape": "sphere", "radius": _local_radius(probe) if probe.type == "MESH" else probe.empty_display_size}


def scene_dict(scene, settings):
    """The hapticfluid.bake scene dict (JSON form) for the current Blender scene and settings."""
    lo, hi = domain_box(settings)
    if settings.frame_end < settings.frame_start:
        raise SceneError(f"the end frame ({settings.frame_end}) is before the start frame ({settings.frame_start})")
    fps = scene.render.fps / scene.render.fps_base
    data = {
        "domain": {"origin": lo, "size": [hi[i] - lo[i] for i in range(3)]},
        "resolution": settings.resolution,
        "fluid": fluid_dict(scene, settings),
        "frames": {"start": settings.frame_start, "end": settings.frame_end, "fps": fps},
        "substeps": "adaptive" if settings.adaptive_substeps else settings.substeps,
        "cfl": settings.cfl,
        "max_substeps": settings.max_substeps,
        "cache": {
            "directory": cache_folder(settings),
            "grids": ["density"] + (["velocity"] if settings.write_velocity else [])
                     + (["pressure"] if settings.write_pressure else []),
            "compression": settings.compression,
            "half_float": settings.half_float,
            "tolerance": settings.tolerance,
        },
    }
    source = source_dict(settings)
    if source is not None:
        data["source"] = source
    if settings.probe is not None:
        probe = settings.probe
        shape = probe_shape_dict(probe, settings.probe_shape)
        keys = []
        current = scene.frame_current
        try:
            for frame in range(settings.frame_start - 1, settings.frame_end + 1):
                scene.frame_set(frame)
                keys.append({"frame": frame, "matrix": [list(row) for row in probe.matrix_world]})
        finally:
            scene.frame_set(current)
        data["probe"] = {**shape, "keys": keys}
    return data
