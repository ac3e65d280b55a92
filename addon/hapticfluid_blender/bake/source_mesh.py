# SPDX-License-Identifier: GPL-3.0-or-later
"""The smoke source object -> the bake scene's "source" (main thread only: reads bpy).

A mesh object emits from its volume (Mantaflow's flow object with Flow Source: Mesh): its
evaluated mesh (modifiers applied) in object space, and its matrix_world at every baked frame
(the caller samples it alongside the probe's, see blender_scene.scene_dict), so it can be
animated. An Empty stays a sphere of its display size. The source object is hidden from renders
while it has the role, as Mantaflow's flow objects usually are; its own setting comes back when
the role goes (sync_render_visibility).
"""

import bpy

from ..properties import roles

# Custom property on an object hidden from renders because it is a smoke source: its
# hide_render from before, restored when it stops being one.
HIDDEN_KEY = "hapticfluid_source_hide_render"


class SourceError(Exception):
    """The source object cannot be a smoke source; the message starts with the fix."""


def _mesh_problem(vertices, triangles):
    """None for a closed, consistently oriented mesh (as the engine requires: vertices at the same
    position merged, every edge used once in each direction), else the number of open edges."""
    import numpy as np

    if len(triangles) == 0:
        return 0
    _, weld = np.unique(np.asarray(vertices, dtype=np.float32), axis=0, return_inverse=True)
    t = weld.reshape(-1)[np.asarray(triangles, dtype=np.int64)]
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    directed = directed[directed[:, 0] != directed[:, 1]]  # collapsed triangles' zero-length edges
    n = int(weld.max()) + 1
    forward = directed[:, 0] * n + directed[:, 1]
    backward = directed[:, 1] * n + directed[:, 0]
    keys, counts = np.unique(forward, return_counts=True)
    back_keys, back_counts = np.unique(backward, return_counts=True)
    table = dict(zip(back_keys.tolist(), back_counts.tolist()))
    unmatched = sum(abs(c - table.get(k, 0)) for k, c in zip(keys.tolist(), counts.tolist()))
    unmatched += sum(c for k, c in table.items() if k not in set(keys.tolist()))
    return None if unmatched == 0 else unmatched // 2 + unmatched % 2


def evaluated_mesh(obj):
    """The object's evaluated mesh (modifiers applied) in its local frame, for the probe and the
    source: (vertices, triangles, flat), where ``flat`` is None or why the mesh can enclose no
    volume ("has no faces", "is flat (...)")."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        vertices = [list(v.co) for v in mesh.vertices]
        triangles = [list(t.vertices) for t in mesh.loop_triangles]
    finally:
        evaluated.to_mesh_clear()
    extent = [max(v[i] for v in vertices) - min(v[i] for v in vertices) for i in range(3)] if vertices else [0.0] * 3
    flat = None
    if len(triangles) < 4 or min(extent) <= 1e-9 * max(max(extent), 1e-30):
        flat = ("has no faces" if not triangles
                else f"is flat ({len(triangles)} triangle(s), extent {[round(e, 4) for e in extent]} m)")
    return vertices, triangles, flat


def mesh_arrays(obj):
    """The source object's evaluated mesh in its local frame: {"vertices", "triangles"}. Raises
    SourceError (fix first, naming the object) for a mesh with no volume or with holes."""
    vertices, triangles, flat = evaluated_mesh(obj)
    if flat is not None:
        raise SourceError(f"give the smoke source '{obj.name}' a closed mesh with thickness (e.g. a Solidify "
                          f"modifier), or use an Empty for a sphere source: smoke comes from the mesh's volume, "
                          f"and it {flat}")
    open_edges = _mesh_problem(vertices, triangles)
    if open_edges is not None:
        raise SourceError(f"close the smoke source '{obj.name}' mesh (Edit Mode: Mesh > Clean Up > Fill Holes, then "
                          f"Mesh > Normals > Recalculate Outside): smoke comes from the mesh's volume, and "
                          f"{open_edges} of its edges are open or join faces that point different ways")
    return {"vertices": vertices, "triangles": triangles}


def values(settings):
    """The emitted values (the Source sub-panel): concentration and K above ambient, held."""
    return {"density": settings.source_density, "temperature": settings.source_temperature}


def source_dict(settings):
    """The smoke source at the current frame, or None: a mesh object as {"shape": "mesh",
    vertices, triangles, "matrix"} (matrix_world as rows; the bake replaces it with per-frame
    keys), an Empty or other object without a mesh as a sphere {"centre", "radius"} (m)."""
    src = settings.source
    if src is None:
        return None
    if src.type == "MESH":
        return {"shape": "mesh", **mesh_arrays(src), "matrix": [list(row) for row in src.matrix_world],
                **values(settings)}
    radius = 0.5 * max(src.dimensions)
    if radius <= 0.0:  # an empty: use its display size
        radius = src.empty_display_size * max(abs(s) for s in src.matrix_world.to_scale())
    return {"centre": list(src.matrix_world.translation), "radius": radius, **values(settings)}


def sync_render_visibility(_obj=None, _role=None):
    """Hide every scene's smoke source from renders and give any object that is no longer one
    its own hide_render back (run when a role changes: object_props.ROLE_CHANGED_HOOKS; safe to
    call any time)."""
    sources = {obj.name for obj in bpy.data.objects if roles.role_of(obj) == "SOURCE"}
    for obj in bpy.data.objects:
        if obj.name in sources:
            if HIDDEN_KEY not in obj:
                obj[HIDDEN_KEY] = bool(obj.hide_render)
                obj.hide_render = True
        elif HIDDEN_KEY in obj:
            obj.hide_render = bool(obj[HIDDEN_KEY])
            del obj[HIDDEN_KEY]
