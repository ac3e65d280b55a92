# SPDX-License-Identifier: GPL-3.0-or-later
"""Closed triangle meshes for mesh probes, tests and benchmarks (local frame, metres).

Each function returns ``(vertices, triangles)``: float32 (N, 3) and int32 (M, 3), triangles
counter-clockwise seen from outside, ready for ``Simulation.set_mesh_probe``.
"""

from typing import Dict, List, Sequence, Tuple

import numpy as np
import numpy.typing as npt

Mesh = Tuple[npt.NDArray[np.float32], npt.NDArray[np.int32]]


def box(size: Sequence[float]) -> Mesh:
    """An axis-aligned box of edges ``size`` (m) centred on the origin: 8 vertices, 12 triangles."""
    half = 0.5 * np.asarray(size, dtype=np.float64)
    if half.shape != (3,) or not np.all(np.isfinite(half)) or np.any(half <= 0):
        raise ValueError(f"box size must be three positive finite lengths (m), got {size!r}")
    corners = np.array([[(1 if i & 1 else -1), (1 if i & 2 else -1), (1 if i & 4 else -1)] for i in range(8)])
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = [t for a, b, c, d in faces for t in ((a, b, c), (a, c, d))]
    return (corners * half).astype(np.float32), np.array(tris, dtype=np.int32)


def icosphere(levels: int, radius: float) -> Mesh:
    """A sphere of ``radius`` (m) at the origin: an icosahedron split ``levels`` times
    (20 * 4**levels triangles; 0 <= levels <= 7), its vertices on the sphere."""
    if not 0 <= levels <= 7:
        raise ValueError(f"levels must be between 0 and 7, got {levels}")
    if not np.isfinite(radius) or radius <= 0:
        raise ValueError(f"radius must be positive and finite (m), got {radius}")
    t = (1.0 + 5.0 ** 0.5) / 2.0
    verts: List[npt.NDArray[np.float64]] = [
        np.array(p, dtype=np.float64) / np.linalg.norm(p)
        for p in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                  (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    ]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        middle: Dict[Tuple[int, int], int] = {}

        def mid(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in middle:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                middle[key] = len(verts) - 1
            return middle[key]

        split = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = split
    return (np.array(verts) * radius).astype(np.float32), np.array(faces, dtype=np.int32)


def uv_sphere(slices: int, rings: int, radius: float) -> Mesh:
    """A sphere of ``radius`` (m) at the origin from ``slices`` meridians and ``rings`` parallels
    (plus the two poles): exactly ``2 * slices * rings`` triangles (slices >= 3, rings >= 1)."""
    if slices < 3 or rings < 1:
        raise ValueError(f"a UV sphere needs slices >= 3 and rings >= 1, got {slices}, {rings}")
    if not np.isfinite(radius) or radius <= 0:
        raise ValueError(f"radius must be positive and finite (m), got {radius}")
    theta = np.pi * np.arange(1, rings + 1) / (rings + 1)  # polar angle of each parallel
    phi = 2.0 * np.pi * np.arange(slices) / slices
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.outer(np.cos(theta), np.ones(slices))], axis=-1).reshape(-1, 3)
    vertices = np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]]) * radius
    north, south = 0, 1 + rings * slices
    s = np.arange(slices)
    s1 = (s + 1) % slices
    tris = [np.stack([np.full(slices, north), 1 + s, 1 + s1], axis=1)]
    for r in range(rings - 1):
        a, b = 1 + r * slices, 1 + (r + 1) * slices
        tris.append(np.stack([a + s, b + s, b + s1], axis=1))
        tris.append(np.stack([a + s, b + s1, a + s1], axis=1))
    last = 1 + (rings - 1) * slices
    tris.append(np.stack([np.full(slices, south), last + s1, last + s], axis=1))
    return vertices.astype(np.float32), np.vstack(tris).astype(np.int32)


def volume(vertices: npt.ArrayLike, triangles: npt.ArrayLike) -> float:
    """Enclosed volume (m^3) of a closed mesh, by the divergence theorem (signed tetrahedra)."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
