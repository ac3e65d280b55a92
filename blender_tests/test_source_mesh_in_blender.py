# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: a mesh smoke source.
An animated cube is the source: the scene export carries its evaluated mesh in object space and
its matrix_world at every frame; the bake puts the smoke where the cube was (and nowhere else);
the source is hidden from renders while it has the role and gets its own setting back when the
role goes; an open or a flat source mesh is refused with a report that names the object and
starts with the fix; an Empty still gives a sphere source."""

import os
import tempfile

import bpy
import numpy as np

from support import bake_scene, check, cube, key_locations, refused, remove_on_exit

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)

RES = 24  # cells along the 1 m domain
H = 1.0 / RES
EDGE = 0.2  # m, the cube source (size 0.1 m scaled by 2)
PATH = ((1, (0.3, 0.5, 0.25)), (4, (0.6, 0.5, 0.25)))  # the source's keyed location


def density(path):
    from hapticfluid.bake.openvdb_python import import_openvdb

    vdb = import_openvdb()
    check(vdb is not None, "OpenVDB's Python module imports (pyopenvdb or openvdb)")

    grid = vdb.read(path, "density")
    out = np.zeros((RES, RES, RES), dtype=np.float32)
    grid.copyToArray(out, ijk=(0, 0, 0))
    return out


def build(cache_dir):
    # The probe moves along the top, away from the smoke; no buoyancy, vorticity or fading, so
    # the smoke stays close to where it was emitted.
    scene, s, _, _, sphere = bake_scene(cache_dir, resolution=RES, probe_radius=0.08,
                                        probe_path=((1, (0.3, 0.5, 0.8)), (4, (0.6, 0.5, 0.8))))
    bpy.data.objects.remove(sphere)
    source = cube(0.1, PATH[0][1], "CubeSource")
    source.scale = (2.0, 2.0, 2.0)
    key_locations(source, PATH)
    s.source = source
    s.heat_buoyancy, s.vorticity, s.smoke_dissipation, s.open_top = 0.0, 0.0, 0.0, False
    s.source_density, s.source_temperature = 0.8, 5.0
    s.tolerance, s.half_float = 0.0, False
    return scene, s, source


def check_export(scene, s, source):
    from hapticfluid_blender.bake import blender_scene

    data = blender_scene.scene_dict(scene, s)["source"]
    check(data["shape"] == "mesh" and len(data["triangles"]) == 12 and len(data["vertices"]) == 8,
          f"the cube source is exported as its mesh ({len(data['vertices'])} vertices, "
          f"{len(data['triangles'])} triangles)")
    v = np.asarray(data["vertices"])
    check(np.allclose(np.abs(v), 0.05), "its vertices are in object space (the 0.1 m cube, scale not applied)")
    frames = [k["frame"] for k in data["keys"]]
    check(frames == list(range(0, 5)), f"a matrix_world key per frame from start - 1 to end: {frames}")
    for key in data["keys"]:
        scene.frame_set(key["frame"])
        world = [list(row) for row in source.matrix_world]
        check(np.allclose(key["matrix"], world), f"frame {key['frame']}: the key is matrix_world "
                                                 f"(x {key['matrix'][0][3]:.3f} m, scale {key['matrix'][0][0]:g})")
    scene.frame_set(1)
    check(data["density"] == s.source_density and data["temperature"] == s.source_temperature,
          "the Source sub-panel's density and temperature go with it")


def check_bake(s, cache_dir):
    result = bpy.ops.hapticfluid.bake()
    check(result == {"FINISHED"}, f"the bake with a mesh source finished ({result}, status: {s.status})")
    d = density(os.path.join(cache_dir, "data", "fluid_data_0004.vdb"))
    x = (np.arange(RES) + 0.5) * H
    per_x, per_y, per_z = d.sum(axis=(1, 2)), d.sum(axis=(0, 2)), d.sum(axis=(0, 1))
    lo, hi = PATH[0][1][0] - EDGE / 2, PATH[1][1][0] + EDGE / 2  # the x the cube swept
    inside = per_x[(x > lo - H) & (x < hi + H)].sum()
    check(inside >= 0.99 * per_x.sum() > 0, f"frame 4: {inside / per_x.sum():.4f} of the smoke lies where the cube "
                                            f"swept (x {lo:.2f} .. {hi:.2f} m, give or take a cell)")
    for axis, per, centre in (("y", per_y, PATH[0][1][1]), ("z", per_z, PATH[0][1][2])):
        band = (x > centre - EDGE / 2 - H) & (x < centre + EDGE / 2 + H)
        check(per[band].sum() >= 0.99 * per.sum(), f"and in the cube's {axis} band ({centre - EDGE / 2:.2f} .. "
                                                   f"{centre + EDGE / 2:.2f} m)")
    # the cube was at x = 0.3 .. 0.6 m over frames 1-4: smoke at both ends of its path
    for where in (PATH[0][1][0], PATH[1][1][0]):
        i = int(where / H)
        check(per_x[i] > 0.2 * per_x.max(), f"smoke where the cube was at x = {where} m")
    check(0.6 <= d.max() <= 0.8 + 1e-4, f"held at most at the source density (peak {d.max():.3f})")
    d1 = density(os.path.join(cache_dir, "data", "fluid_data_0001.vdb"))
    p1 = d1.sum(axis=(1, 2))
    centre = (p1 * x).sum() / p1.sum()
    check(abs(centre - PATH[0][1][0]) < 2 * H, f"frame 1: the smoke is centred on the cube (x {centre:.3f} m)")


def check_render_visibility(s, source):
    check(source.hide_render, "the mesh source is hidden from renders while it is the source")
    s.source = None
    check(not source.hide_render, "and shown again when the role is removed")
    source.hide_render = True  # the artist's own choice survives a round trip
    s.source = source
    other = cube(0.1, (0.5, 0.5, 0.5), "Other")
    s.source = other
    check(source.hide_render and other.hide_render,
          "a source hidden before keeps hide_render when replaced; the new source is hidden")
    s.source = None
    check(not other.hide_render and source.hide_render, "each gets its own setting back")
    bpy.data.objects.remove(other)
    source.hide_render = False
    s.source = source


def check_refused(s, source):
    open_cube = cube(0.2, (0.5, 0.5, 0.3), "OpenCube")
    mesh = open_cube.data
    import bmesh

    bm = bmesh.new()
    bm.from_mesh(mesh)
    bm.faces.ensure_lookup_table()
    bm.faces.remove(bm.faces[0])
    bm.to_mesh(mesh)
    bm.free()
    s.source = open_cube
    text = refused(bpy.ops.hapticfluid.bake, "close the smoke source 'OpenCube' mesh", "Fill Holes", "open")
    check(text.index("close the smoke source") < text.index("open"), "the fix comes first")
    check(s.status.startswith("bake not started: close the smoke source 'OpenCube'"),
          f"the status line says it too: {s.status}")
    bpy.ops.mesh.primitive_plane_add(size=0.3, location=(0.5, 0.5, 0.3))
    plane = bpy.context.active_object
    plane.name = "FlatSource"
    s.source = plane
    refused(bpy.ops.hapticfluid.bake, "give the smoke source 'FlatSource' a closed mesh with thickness",
            "Solidify", "flat")
    bpy.ops.object.empty_add(location=(0.5, 0.5, 0.3))
    empty = bpy.context.active_object
    empty.empty_display_size = 0.1
    s.source = empty
    from hapticfluid_blender.bake import blender_scene

    data = blender_scene.source_dict(s)
    check("shape" not in data and abs(data["radius"] - 0.1) < 1e-6 and np.allclose(data["centre"], (0.5, 0.5, 0.3)),
          f"an Empty is still a sphere source: {data}")
    for obj in (open_cube, plane, empty):
        bpy.data.objects.remove(obj)
    s.source = source


def main():
    hapticfluid_blender.register()
    tmp = remove_on_exit(tempfile.mkdtemp(prefix="hf_blender_source_"))
    cache = os.path.join(tmp, "cache")
    scene, s, source = build(cache)
    check_export(scene, s, source)
    check_render_visibility(s, source)
    check_refused(s, source)
    check_bake(s, cache)
    hapticfluid_blender.unregister()
    print("source mesh in Blender: all checks passed")


main()
