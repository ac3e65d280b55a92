# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh input limits are checked before the arrays are copied (review fix)."""

import tracemalloc

import numpy as np
import pytest

import hapticfluid as hf


def test_oversized_mesh_is_refused_before_it_is_copied():
    too_many = 10_000_001  # one over the engine's limit of vertices (and of triangles)
    # Broadcast views: no memory of their own, but a full copy would need ~120 MB each.
    vertices = np.broadcast_to(np.float64(0.25), (too_many, 3))
    triangles = np.broadcast_to(np.int64(0), (too_many, 3))
    with hf.Simulation(resolution=(8, 8, 8), domain_size=(1.0, 1.0, 1.0), pressure_iterations=1) as sim:
        tracemalloc.start()
        try:
            with pytest.raises(hf.InvalidArgumentError, match="at most 10000000 of each"):
                sim.set_mesh_probe(vertices, triangles)
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        assert sim.probe is None
    assert peak < 16 * 2 ** 20, f"{peak / 2 ** 20:.0f} MiB allocated to refuse the mesh"
