# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: the live viewport
drawing (live_draw) never touches gpu in background mode (add/remove are no-ops, twice is fine,
the setters store and validate without raising), bad values raise ValueError naming the
argument, and the pure geometry it draws has the known answers: box faces wound outwards, the
arrow's length, cap, tip and winding, the colour ramp, the light's optical depth and the texel
layout of the uploaded field."""

import math

import bpy
import numpy as np
from mathutils import Vector

from support import check
from hapticfluid_blender.live import live_draw, live_draw_geometry as geometry  # noqa: E402


def raises(call, word):
    try:
        call()
    except ValueError as error:
        return word in str(error)
    return False


def background_no_ops():
    check(bpy.app.background, "running in --background")
    drawer = live_draw.LiveDrawer()
    for _ in range(2):
        drawer.add()
    check(not drawer.is_added and not live_draw._active, "add() twice adds no handler in background")
    drawer.set_domain((0.0, 0.0, 0.0), (1.0, 2.0, 0.5))
    density = np.random.default_rng(1).random((8, 16, 4), dtype=np.float32)
    drawer.set_density(np.asfortranarray(density), temperature=8.0 * density)
    drawer.set_density(density)
    drawer.set_force((0.5, 0.5, 0.25), (1.0, 0.0, 0.0), 3.0)
    drawer.set_workspace_box((0.1, 0.1, 0.1), (0.9, 1.9, 0.4))
    drawer.set_workspace_box((0.1, 0.1, 0.1), None)
    drawer.set_display(35.0, True)
    check(drawer.density_scale == 35.0 and drawer.show_temperature, "set_display stores its values")
    check(drawer.frames_drawn == 0 and drawer.uploads == 0 and drawer.sampling is None,
          "nothing was drawn, uploaded or compiled")
    for _ in range(2):
        drawer.remove()
    live_draw.remove_all()
    check(not drawer.is_added, "remove() twice and remove_all() are fine")


def bad_values():
    drawer = live_draw.LiveDrawer()
    check(raises(lambda: drawer.set_domain((0, 0, 0), (1, 0, 1)), "hi_m"), "a flat domain names hi_m")
    check(raises(lambda: drawer.set_domain((0, 0), (1, 1, 1)), "lo_m"), "a 2-number corner names lo_m")
    check(raises(lambda: drawer.set_density(np.zeros((4, 4), np.float32)), "array_xyz_float32"),
          "a 2D array names array_xyz_float32")
    check(raises(lambda: drawer.set_density(np.full((2, 2, 2), np.nan, np.float32)), "non-finite"),
          "NaN density is refused")
    check(raises(lambda: drawer.set_density(np.zeros((2, 2, 2)), np.zeros((2, 2, 3))), "temperature"),
          "a temperature of another shape names temperature")
    check(raises(lambda: drawer.set_force((0, 0, 0), (1, 0, 0), 0.0), "max_force_n"), "max_force_n 0 is refused")
    check(raises(lambda: drawer.set_force((0, 0, 0), (1, 0, math.inf), 1.0), "force_n"), "an infinite force is refused")
    check(raises(lambda: drawer.set_display(-1.0, False), "density_scale"), "a negative density_scale is refused")
    check(raises(lambda: drawer.set_workspace_box((0, 0, 0), (1, 1, -1)), "hi_m_or_None"),
          "an inverted workspace box names hi_m_or_None")


def box_geometry():
    lo, hi = (0.0, -1.0, 2.0), (1.0, 1.0, 3.0)
    corners = [Vector(c) for c in geometry.box_corners(lo, hi)]
    check(tuple(corners[0]) == lo and tuple(corners[7]) == hi and tuple(corners[5]) == (1.0, -1.0, 3.0),
          "corner i takes hi on axis a when bit a is set")
    centre = (corners[0] + corners[7]) / 2
    outward = all(((corners[b] - corners[a]).cross(corners[c] - corners[a])).dot(
        (corners[a] + corners[b] + corners[c]) / 3 - centre) > 0 for a, b, c in geometry.BOX_TRIANGLES)
    check(len(geometry.BOX_TRIANGLES) == 12 and outward, "the box's 12 triangles wind outwards")
    lengths = sorted(round((corners[b] - corners[a]).length, 6) for a, b in geometry.BOX_EDGES)
    check(lengths == [1.0] * 8 + [2.0] * 4, f"12 edges, 4 along each axis: {lengths}")


def arrow_geometry():
    diagonal = math.sqrt(3.0)
    check(math.isclose(geometry.arrow_length_m(3.0, 3.0, diagonal), 0.25 * diagonal),
          "max_force_n gives a quarter of the diagonal")
    full = 0.25 * diagonal
    decade = [geometry.arrow_length_m(3.0 * 10.0 ** -k, 3.0, diagonal) / full for k in range(4)]
    check(math.isclose(decade[1], math.log10(101.0) / math.log10(1001.0))
          and math.isclose(decade[3], math.log10(2.0) / math.log10(1001.0)),
          f"the length grows with the log of the force over 3 decades: max, /10, /100, /1000 -> "
          f"{[round(d, 3) for d in decade]} of max's length")
    check(geometry.arrow_length_m(0.036, 4.0, diagonal) > 0.3 * full,
          "a gentle 0.036 N hand force against a 4 N device is over a third of the full arrow (readable)")
    check(math.isclose(geometry.arrow_length_m(30.0, 3.0, diagonal), geometry.arrow_length_m(6.0, 3.0, diagonal))
          and geometry.arrow_length_m(6.0, 3.0, diagonal) > full,
          "a force far above max stops growing at twice max")
    origin, force = Vector((0.2, 0.3, 0.4)), Vector((0.0, 1.2, -1.6))
    positions, colours, tip = geometry.arrow_mesh(origin, force, 3.0, diagonal)
    length = geometry.arrow_length_m(2.0, 3.0, diagonal)
    check((Vector(tip) - (origin + force.normalized() * length)).length < 1e-9, "the tip lies along the force")
    check(len(positions) == len(colours) and len(positions) % 3 == 0, "one colour per vertex of whole triangles")
    axis = force.normalized()
    ref = geometry.ARROW_FRACTION_OF_DIAGONAL * diagonal
    shaft_r = geometry.ARROW_SHAFT_RADIUS * ref
    neck = origin + axis * (length - min(geometry.ARROW_HEAD_LENGTH * ref, 0.5 * length))
    shaft_centre, cone_centre = (origin + neck) / 2, neck + axis * (Vector(tip) - neck).length / 4
    wrong = 0
    for i in range(0, len(positions), 3):
        a, b, c = (Vector(p) for p in positions[i:i + 3])
        radial = max(((p - origin) - axis * (p - origin).dot(axis)).length for p in (a, b, c))
        centre = shaft_centre if radial <= shaft_r * 1.0001 else cone_centre
        wrong += (b - a).cross(c - a).dot((a + b + c) / 3 - centre) <= 0
    check(wrong == 0, f"every arrow triangle winds outwards ({len(positions) // 3} triangles)")
    check(geometry.arrow_mesh(origin, (0.0, 0.0, 0.0), 3.0, diagonal) is None, "no arrow for a zero force")
    small = geometry.arrow_mesh(origin, force * 0.01, 3.0, diagonal)[0]
    width = max(((Vector(p) - origin) - axis * (Vector(p) - origin).dot(axis)).length for p in small)
    small_length = geometry.arrow_length_m(0.02, 3.0, diagonal)
    check(math.isclose(width, geometry.ARROW_HEAD_RADIUS / geometry.ARROW_HEAD_LENGTH * small_length / 2,
                       rel_tol=1e-4), f"a weak force's arrow is a scaled-down arrow, not a disc ({width:.6f} m wide "
                                   f"over {small_length:.5f} m)")
    check(geometry.force_color(0.0, 3.0)[:3] == (0.25, 0.9, 0.2) and geometry.force_color(9.0, 3.0)[:3] ==
          geometry.force_color(3.0, 3.0)[:3] and geometry.force_color(3.0, 3.0)[0] == 1.0,
          "green at zero, red from max_force_n up")
    labels = [geometry.label_text(f) for f in (3.2, 0.456, 12.34, 0.0359)]
    check(labels == ["3.2 N on the hand", "0.46 N on the hand", "12.3 N on the hand", "0.036 N on the hand"],
          f"labels read {labels}")


def field_layout():
    density = np.zeros((3, 2, 4), np.float32)
    density[1, 0, :] = 1.0
    depth = geometry.optical_depth_above(density, 0.25)
    check(np.allclose(depth[1, 0], [0.875, 0.625, 0.375, 0.125]) and not depth[0].any(),
          "optical depth above: half the own cell plus every cell above, times the cell height")
    rng = np.random.default_rng(2)
    density, temperature = rng.random((3, 2, 4), np.float32), rng.random((3, 2, 4), np.float32)
    packed = geometry.pack_field(density, temperature, 0.1)
    flat = packed.reshape(-1)
    i, j, k = 2, 1, 3
    texel = 4 * (i + 3 * (j + 2 * k))  # x fastest, as GPUTexture((nx, ny, nz)) reads its data
    check(flat[texel] == density[i, j, k] and flat[texel + 2] == temperature[i, j, k] and flat[texel + 3] == 0.0,
          "texel (i, j, k) holds density, optical depth, temperature, 0 at 4 * (i + nx * (j + ny * k))")


def probe_for_the_smoke():
    """What the smoke's rays stop at: a mesh probe's corners as texels (a fine mesh by its box)."""
    from hapticfluid import meshes

    v, t = meshes.box((0.2, 0.4, 0.6))
    texels = geometry.probe_triangle_texels(v, t)
    check(texels.shape == (36, 4) and texels.dtype == np.float32 and (texels[:, 3] == 1.0).all()
          and np.array_equal(texels[3 * 5 + 2, :3], v[t[5, 2]]), "one texel (x, y, z, 1) per triangle corner")
    v, t = meshes.icosphere(4, 0.1)  # 5120 triangles: more than the shader loops over
    texels = geometry.probe_triangle_texels(v, t)
    check(len(t) > geometry.MAX_PROBE_TRIANGLES and texels.shape == (36, 4)
          and np.allclose(texels[:, :3].min(axis=0), v.min(axis=0)) and np.allclose(texels[:, :3].max(axis=0),
                                                                                    v.max(axis=0)),
          "a finer mesh is stood in for by its local bounding box (12 triangles)")
    check(math.isclose(geometry.sphere_radius_world(0.1, [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 3, 0], [0, 0, 0, 1]]),
                       0.3), "a sphere's world radius: the largest column scale, as the engine")
    drawer = live_draw.LiveDrawer()
    check(raises(lambda: drawer.set_probe({"shape": "sphere", "radius": 0.0}), "radius"), "a zero radius is refused")
    check(raises(lambda: drawer.set_probe({"shape": "cone"}), "shape"), "an unknown shape is refused")
    check(raises(lambda: drawer.set_probe({"shape": "mesh", "vertices": [(0, 0, 0)], "triangles": [(0, 1, 2)]}),
                 "triangles"), "triangles indexing missing vertices are refused")
    check(raises(lambda: drawer.set_probe_matrix(np.zeros((4, 4))), "matrix_world"), "a singular matrix is refused")
    rng = np.random.default_rng(7)
    worst = max(abs(geometry.det3(m) - np.linalg.det(m[:3, :3])) / max(1.0, abs(np.linalg.det(m[:3, :3])))
                for m in rng.normal(size=(50, 4, 4)))
    check(worst < 1e-12 and geometry.det3([[0, 1, 0], [1, 0, 0], [0, 0, 2]]) == -2.0,
          f"det3 is the 3 x 3 determinant (worst relative difference {worst:.1e})")
    # The per-redraw and per-tick paths call no numpy.linalg (LAPACK wakes OpenBLAS's worker, which spins).
    saved = np.linalg.det, np.linalg.inv

    def no_lapack(*_args, **_kwargs):
        raise AssertionError("numpy.linalg called")
    np.linalg.det = np.linalg.inv = no_lapack
    try:
        drawer.set_probe({"shape": "sphere", "radius": 0.1})
        drawer.set_probe_matrix(np.eye(4))
        drawer.set_probe_matrix([[2, 0, 0, 0.1], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    finally:
        np.linalg.det, np.linalg.inv = saved
    drawer.set_probe(None)


def smoke_budget():
    """The time budget's pure parts: the box of cells the march walks, the next pixel scale and a
    mesh probe's bounding sphere (the triangle loop runs only for rays through it)."""
    density = np.zeros((8, 6, 10), np.float32)
    check(geometry.occupied_cells(density) is None, "no smoke: nothing to march")
    density[3, 2, 4] = 0.5
    density[5, 2, 7] = geometry.EMPTY_DENSITY  # at the cut-off: empty
    cells = geometry.occupied_cells(density)
    check(cells == ((2, 1, 3), (5, 4, 6)), f"one smoky cell and a cell of margin: {cells}")
    density[7, 5, 9] = 1.0
    check(geometry.occupied_cells(density) == ((2, 1, 3), (8, 6, 10)), "the margin stops at the grid's edge")
    lo, hi = geometry.cells_to_world(((2, 1, 3), (5, 4, 6)), (0.0, 0.0, 0.0), (0.8, 0.6, 1.0), (8, 6, 10))
    check(np.allclose(lo, (0.2, 0.1, 0.3)) and np.allclose(hi, (0.5, 0.4, 0.6)), f"cells to metres: {lo} {hi}")
    nxt = geometry.next_pixel_scale
    check(nxt(0.5, 80.0, 20.0, 0.125, 0.5) == 0.375, "4x over budget: half way to half the pixels per axis")
    check(nxt(0.25, 1000.0, 20.0, 0.125, 0.5) == 0.125, "never below the lowest scale")
    check(nxt(0.25, 1.0, 20.0, 0.125, 0.5) == 0.5, "well under budget: back up, not above the highest")
    check(nxt(0.25, 15.0, 20.0, 0.125, 0.5) == 0.25, "a little under budget: kept (no flicker between scales)")
    check(nxt(0.25, 0.0, 20.0, 0.125, 0.5) == 0.25, "no measurement: kept")
    check(nxt(0.25, 30.0, math.inf, 0.125, 0.5) == 0.5, "no budget: the highest scale")
    check(all(abs(nxt(s, m, 20.0, 0.125, 0.5) / geometry.PIXEL_SCALE_STEP % 1.0) < 1e-9
              for s in (0.125, 0.3125, 0.5) for m in (3.0, 19.0, 41.0, 300.0)), "scales come in steps")
    corners = np.array([[1.0, 2.0, 3.0], [1.2, 2.0, 3.0], [1.0, 2.4, 3.0], [1.0, 2.0, 2.6]])
    cx, cy, cz, r = geometry.bounding_sphere(corners)
    check(np.allclose((cx, cy, cz), (1.1, 2.2, 2.8)) and all(
        math.dist((cx, cy, cz), p) <= r for p in corners), f"a bounding sphere holds every corner: {cx, cy, cz, r}")


background_no_ops()
bad_values()
smoke_budget()
probe_for_the_smoke()
box_geometry()
arrow_geometry()
field_layout()
print("blender live draw background test passed")
