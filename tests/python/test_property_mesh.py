# SPDX-License-Identifier: GPL-3.0-or-later
"""Property-based tests (hypothesis) of the mesh checks in set_mesh_probe: any closed, consistently
oriented mesh that fits loads; any other input raises InvalidArgumentError (a ValueError) with a
message, never anything else; a refused mesh leaves the previous probe in place."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import hapticfluid as hf
from hapticfluid import meshes

SETTINGS = settings(max_examples=40, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


@pytest.fixture(scope="module")
def sim():
    return hf.Simulation(resolution=(16, 16, 16), pressure_iterations=2)


def moved(x, y, z, s=1.0):
    m = np.diag([s, s, s, 1.0])
    m[:3, 3] = (x, y, z)
    return m


def _load_or_refuse(sim, vertices, triangles, **kwargs):
    sim.set_probe((0.5, 0.5, 0.5), 0.1)
    try:
        sim.set_mesh_probe(vertices, triangles, **kwargs)
    except hf.InvalidArgumentError as exc:
        assert str(exc)
        assert sim.probe["kind"] == "sphere", "a refused mesh replaced the probe"
        return False
    assert sim.probe["kind"] == "mesh"
    return True


@SETTINGS
@given(size=st.tuples(*[st.floats(0.15, 0.4)] * 3), centre=st.tuples(*[st.floats(0.4, 0.6)] * 3),
       levels=st.integers(0, 2), shape=st.sampled_from(["box", "icosphere"]))
def test_closed_meshes_that_fit_load(sim, size, centre, levels, shape):
    v, t = meshes.box(size) if shape == "box" else meshes.icosphere(levels, min(size) / 2)
    assert _load_or_refuse(sim, v, t, transform=moved(*centre))


@SETTINGS
@given(drop=st.integers(0, 11), flip=st.booleans())
def test_opened_or_flipped_boxes_are_refused(sim, drop, flip):
    v, t = meshes.box((0.2, 0.2, 0.2))
    t = np.array(t)
    if flip:
        t[drop] = t[drop][::-1]
    else:
        t = np.delete(t, drop, axis=0)
    assert not _load_or_refuse(sim, v, t, transform=moved(0.5, 0.5, 0.5))


finite = st.floats(-2.0, 2.0, allow_nan=False, width=32) | st.sampled_from([np.nan, np.inf, -np.inf, 2.0 ** 60, 0.0])


@SETTINGS
@given(vertices=hnp.arrays(st.sampled_from([np.float32, np.float64]), hnp.array_shapes(min_dims=1, max_dims=3,
                                                                                     max_side=12), elements=finite),
       triangles=hnp.arrays(st.sampled_from([np.int32, np.int64, np.int16, np.float32]),
                            hnp.array_shapes(min_dims=1, max_dims=3, max_side=12),
                            elements=st.integers(-3, 14)))
def test_any_arrays_load_or_are_refused(sim, vertices, triangles):
    _load_or_refuse(sim, vertices, triangles, transform=moved(0.5, 0.5, 0.5, 0.2))


@SETTINGS
@given(n_vertices=st.integers(4, 12), data=st.data())
def test_random_triangle_soups_load_or_are_refused(sim, n_vertices, data):
    v = data.draw(hnp.arrays(np.float64, (n_vertices, 3), elements=st.floats(-0.15, 0.15)))
    t = data.draw(hnp.arrays(np.int64, (data.draw(st.integers(1, 20)), 3), elements=st.integers(0, n_vertices - 1)))
    _load_or_refuse(sim, v, t, transform=moved(0.5, 0.5, 0.5))
