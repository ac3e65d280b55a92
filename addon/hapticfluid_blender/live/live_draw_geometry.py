# SPDX-License-Identifier: GPL-3.0-or-later
"""Pure geometry and colour of the live viewport drawing (no gpu, no bpy: tested headless):
the domain box, the force arrow mesh, its colour and label, the light's optical depth and the
smoke texture's texel layout. Positions in metres, forces in newtons."""

import math

import numpy as np

# The arrow for max_force_n is this fraction of the domain's diagonal long.
ARROW_FRACTION_OF_DIAGONAL = 0.25
# The arrow's length grows with the log of the force over this many decades below max_force_n, so a
# hand force of 1% of the device's limit (typical of a gentle stir) is a third of the full arrow,
# not an invisible 1% of it; the label gives the exact newtons.
ARROW_DECADES = 3.0
# Arrows for forces above max_force_n grow up to this multiple of max_force_n, then stop growing
# (the label still shows the true magnitude).
ARROW_MAX_OVERSHOOT = 2.0
# Arrow proportions, as fractions of the max_force_n arrow's length: shaft and head radius, head length
# (the head is at most half of a short arrow, which then thins in proportion).
ARROW_SHAFT_RADIUS = 0.04
ARROW_HEAD_RADIUS = 0.1
ARROW_HEAD_LENGTH = 0.3


def vec3(value, name):
    try:
        out = tuple(float(v) for v in value)
    except TypeError:
        raise ValueError(f"{name} must be 3 numbers (m), got {value!r}") from None
    if len(out) != 3 or not all(math.isfinite(v) for v in out):
        raise ValueError(f"{name} must be 3 finite numbers, got {value!r}")
    return out


def box(lo_m, hi_m, lo_name, hi_name):
    lo, hi = vec3(lo_m, lo_name), vec3(hi_m, hi_name)
    if not all(h > l for l, h in zip(lo, hi)):
        raise ValueError(f"{hi_name} {hi} must be above {lo_name} {lo} on every axis")
    return lo, hi


def box_corners(lo, hi):
    """The 8 corners of an axis-aligned box, corner i taking hi on axis a when bit a of i is set."""
    return [tuple(hi[a] if (i >> a) & 1 else lo[a] for a in range(3)) for i in range(8)]


# Triangles of the box's 6 faces, counter-clockwise seen from outside (corner indices as above).
BOX_TRIANGLES = (
    (0, 4, 6), (0, 6, 2),  # x = lo
    (1, 3, 7), (1, 7, 5),  # x = hi
    (0, 1, 5), (0, 5, 4),  # y = lo
    (2, 6, 7), (2, 7, 3),  # y = hi
    (0, 2, 3), (0, 3, 1),  # z = lo
    (4, 5, 7), (4, 7, 6),  # z = hi
)
BOX_EDGES = tuple((i, i | (1 << a)) for i in range(8) for a in range(3) if not (i >> a) & 1)


def force_color(magnitude_n, max_force_n):
    """Green at zero, yellow at half of max_force_n, red from max_force_n up (RGBA)."""
    x = min(max(magnitude_n / max_force_n, 0.0), 1.0)
    if x < 0.5:
        return (0.25 + 1.5 * x, 0.9, 0.2, 1.0)
    return (1.0, 0.9 - 1.6 * (x - 0.5), 0.2 - 0.3 * (x - 0.5), 1.0)


def arrow_length_m(magnitude_n, max_force_n, diagonal_m):
    """Arrow length (m): max_force_n is ARROW_FRACTION_OF_DIAGONAL of the diagonal; below, the length
    is log10(1 + F/F0) / log10(1 + max/F0) of that with F0 = max_force_n / 10**ARROW_DECADES (zero at
    zero force, about linear below F0); above max it grows the same way up to ARROW_MAX_OVERSHOOT * max."""
    f0 = max_force_n * 10.0 ** -ARROW_DECADES
    ref = ARROW_FRACTION_OF_DIAGONAL * diagonal_m
    m = min(max(magnitude_n, 0.0), ARROW_MAX_OVERSHOOT * max_force_n)
    return ref * math.log10(1.0 + m / f0) / math.log10(1.0 + max_force_n / f0)


def arrow_mesh(origin, force, max_force_n, diagonal_m, sides=12):
    """Triangles of a shaded 3D arrow from origin along force: (positions, colours, head point).

    None when the force is too small to draw. Arrows longer than twice the head keep the thickness
    of the max_force_n arrow; shorter ones are scaled-down copies of that shape (a cone on a stub).
    Triangles are counter-clockwise from outside.
    """
    from mathutils import Vector

    f = Vector(force)
    magnitude = f.length
    length = arrow_length_m(magnitude, max_force_n, diagonal_m)
    ref = ARROW_FRACTION_OF_DIAGONAL * diagonal_m
    if length < 1e-4 * ref:
        return None
    axis = f / magnitude
    head_len = min(ARROW_HEAD_LENGTH * ref, 0.5 * length)
    thickness = ref * head_len / (ARROW_HEAD_LENGTH * ref)  # a short arrow is a scaled-down one, not a disc
    head_r, shaft_r = ARROW_HEAD_RADIUS * thickness, ARROW_SHAFT_RADIUS * thickness
    o = Vector(origin)
    tip = o + axis * length
    neck = tip - axis * head_len
    u = axis.orthogonal().normalized()
    v = axis.cross(u)
    ring = [u * math.cos(2 * math.pi * k / sides) + v * math.sin(2 * math.pi * k / sides) for k in range(sides)]
    base = force_color(magnitude, max_force_n)
    light = Vector((0.35, -0.45, 0.82)).normalized()

    positions, colours = [], []

    def tri(a, b, c, normal):
        shade = 0.45 + 0.55 * max(normal.dot(light), 0.0)
        rgba = (base[0] * shade, base[1] * shade, base[2] * shade, 1.0)
        positions.extend((tuple(a), tuple(b), tuple(c)))
        colours.extend((rgba, rgba, rgba))

    for k in range(sides):
        r0, r1 = ring[k], ring[(k + 1) % sides]
        mid = (r0 + r1).normalized()
        a0, a1 = o + r0 * shaft_r, o + r1 * shaft_r
        b0, b1 = neck + r0 * shaft_r, neck + r1 * shaft_r
        tri(a0, a1, b1, mid)                                     # shaft side
        tri(a0, b1, b0, mid)
        tri(o, a1, a0, -axis)                                    # shaft cap
        c0, c1 = neck + r0 * head_r, neck + r1 * head_r
        slant = (mid * head_len + axis * head_r).normalized()
        tri(c0, c1, tip, slant)                                  # cone
        tri(neck, c1, c0, -axis)                                 # cone base
    return positions, colours, tuple(tip)


def label_text(magnitude_n):
    """The force label, the force the hand feels: '3.2 N on the hand'; two decimals below 1 N
    ('0.45 N ...'), three below 0.1 N ('0.036 N ...')."""
    digits = 3 if magnitude_n < 0.1 else 2 if magnitude_n < 1.0 else 1
    return f"{magnitude_n:.{digits}f} N on the hand"


def optical_depth_above(density, cell_height_m):
    """Density integrated from each cell's centre up to the domain's top (density * m), [x, y, z]:
    the light from straight above reaches cell k through half of it and all cells above."""
    above = np.cumsum(density[:, :, ::-1], axis=2, dtype=np.float64)[:, :, ::-1]
    return ((above - 0.5 * density) * cell_height_m).astype(np.float32)


def pack_field(density, temperature, cell_height_m):
    """The smoke texture's texels, (z, y, x, 4) C order = x fastest, RGBA per texel: density,
    optical depth above, temperature (0 when None), 0."""
    nx, ny, nz = density.shape
    packed = np.zeros((nz, ny, nx, 4), dtype=np.float32)
    packed[..., 0] = density.transpose(2, 1, 0)
    packed[..., 1] = optical_depth_above(density, cell_height_m).transpose(2, 1, 0)
    if temperature is not None:
        packed[..., 2] = temperature.transpose(2, 1, 0)
    return packed


# The smoke's ray stops at the probe: a mesh probe is intersected triangle by triangle in the
# fragment shader, up to this many triangles; a finer one by its local bounding box's 12.
MAX_PROBE_TRIANGLES = 1024


def probe_triangle_texels(vertices, triangles):
    """A mesh probe's triangles for the smoke shader: float32 (3 * n, 4), one texel per corner
    (local x, y, z, 1), n <= MAX_PROBE_TRIANGLES; above that the local bounding box's 12
    triangles (the ray then stops at the box: conservative, the probe stays visible)."""
    v = np.asarray(vertices, dtype=np.float32).reshape(-1, 3)
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    if len(v) == 0 or len(t) == 0:
        raise ValueError("vertices and triangles must describe at least one triangle")
    if t.min() < 0 or t.max() >= len(v):
        raise ValueError(f"triangles index vertices 0..{len(v) - 1}, got {t.min()}..{t.max()}")
    if len(t) > MAX_PROBE_TRIANGLES:
        v = np.asarray(box_corners(tuple(v.min(axis=0)), tuple(v.max(axis=0))), dtype=np.float32)
        t = np.asarray(BOX_TRIANGLES, dtype=np.int64)
    corners = v[t.reshape(-1)]
    return np.concatenate([corners, np.ones((len(corners), 1), np.float32)], axis=1).astype(np.float32)


def bounding_sphere(points):
    """A sphere holding every point (n, 3): the centre of their box and the farthest point's
    distance from it, a hair larger (float32 rounding in the shader): (x, y, z, radius)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    centre = 0.5 * (p.min(axis=0) + p.max(axis=0))
    radius = float(np.sqrt(((p - centre) ** 2).sum(axis=1).max()))
    return (*(float(c) for c in centre), radius * (1.0 + 1e-4) + 1e-6)


def det3(matrix):
    """The determinant of a matrix's upper-left 3 x 3 (rows), by cofactors. Not numpy.linalg.det:
    a LAPACK call wakes OpenBLAS's worker thread, which then spins beside the drawing (with
    numpy.linalg.inv of a 4 x 4 at a redraw's rate: a whole core)."""
    m = matrix
    return float(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                 + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def sphere_radius_world(radius_local, matrix):
    """A sphere probe's radius in the world: the engine's rule (the largest column scale)."""
    return radius_local * max(math.sqrt(sum(matrix[r][c] ** 2 for r in range(3))) for c in range(3))


# --- the smoke's time budget (live_draw.LiveDrawer on a software renderer) ----------------------

# Density at or below this is empty space: the march skips it (the shader's own cut-off).
EMPTY_DENSITY = 1e-4
# Pixel scales (fraction of the view's pixels per axis) come in steps of this, so the offscreen
# image is not remade for every small change of the budget.
PIXEL_SCALE_STEP = 1.0 / 16.0


def occupied_cells(density, threshold=EMPTY_DENSITY):
    """The box of cells holding smoke, one cell of margin (trilinear filtering reaches half a
    cell past a cell's centre): ((x0, y0, z0), (x1, y1, z1)) as cell indices, x1 exclusive, or None
    when no cell holds more than threshold. The march only walks the rays' part inside it."""
    full = np.asarray(density) > threshold
    if not full.any():
        return None
    lo, hi = [], []
    for axis in range(3):
        others = tuple(a for a in range(3) if a != axis)
        idx = np.flatnonzero(full.any(axis=others))
        lo.append(max(0, int(idx[0]) - 1))
        hi.append(min(full.shape[axis], int(idx[-1]) + 2))
    return tuple(lo), tuple(hi)


def cells_to_world(cells, lo_m, hi_m, shape):
    """occupied_cells' box in the world (m) for a grid of shape filling the box lo_m..hi_m."""
    (c0, c1) = cells
    size = [(hi_m[a] - lo_m[a]) / shape[a] for a in range(3)]
    return (tuple(lo_m[a] + c0[a] * size[a] for a in range(3)), tuple(lo_m[a] + c1[a] * size[a] for a in range(3)))


def next_pixel_scale(scale, march_ms, budget_ms, lowest, highest):
    """The pixel scale for the next march from the last one's cost: the march's cost goes with
    the rays, scale^2, so scale * sqrt(budget / cost), moved half way (one slow frame on a busy
    machine does not halve the picture), in steps of PIXEL_SCALE_STEP within [lowest, highest]."""
    if not (march_ms > 0.0 and budget_ms > 0.0):
        return scale
    wanted = scale * math.sqrt(budget_ms / march_ms)
    if not math.isfinite(wanted):  # no budget (math.inf): the highest scale
        return float(highest)
    step = PIXEL_SCALE_STEP
    moved = scale + 0.5 * (wanted - scale)
    moved = math.floor(moved / step + 0.5) * step if moved < scale else math.floor(moved / step) * step
    return float(min(highest, max(lowest, moved)))
