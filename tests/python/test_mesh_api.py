# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh probes and probe poses through the public API: round trips, copies, and a clear error
(InvalidArgumentError saying what to change) for every kind of bad input, which changes nothing."""

import math

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes
from conftest import step_in_background


def moved(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


@pytest.fixture(scope="module")
def sim():
    """16^3 cells over a 1 m box (h = 1/16 m)."""
    s = hf.Simulation(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0), pressure_iterations=5)
    yield s
    s.close()


def test_mesh_probe_round_trip_and_pose(sim):
    vertices, triangles = meshes.box((0.3, 0.2, 0.25))
    sim.set_mesh_probe(vertices, triangles, moved(0.5, 0.5, 0.5), velocity=(0.1, 0, 0),
                       angular_velocity=(0, 0, 1.0))
    probe = sim.probe
    assert probe["kind"] == "mesh"
    assert probe["vertex_count"] == 8 and probe["triangle_count"] == 12
    np.testing.assert_allclose(probe["transform"], moved(0.5, 0.5, 0.5))
    np.testing.assert_allclose(probe["velocity"], (0.1, 0, 0))
    np.testing.assert_allclose(probe["angular_velocity"], (0, 0, 1.0))
    assert probe["torque_centre"] is None
    report = sim.step(0.01)
    assert report.torque.shape == (3,) and report.torque_centre.shape == (3,)
    assert report.solid_cells > 0
    first = np.argwhere(sim.cell_classes() >= hf.CELL_BOUNDARY).mean(axis=0)

    # The arrays were copied: changing them afterwards changes nothing.
    vertices *= 0.5
    assert sim.step(0.01).solid_cells == report.solid_cells

    # A new pose moves the same mesh (a quarter turn about z, 0.125 m = 2 cells along +x).
    turn = moved(0.625, 0.5, 0.5)
    turn[:2, :2] = [[0.0, -1.0], [1.0, 0.0]]
    sim.set_probe_pose(turn)
    after = sim.step(0.01)
    assert after.solid_cells == report.solid_cells  # a quarter turn maps cell centres onto cell centres
    np.testing.assert_allclose(np.argwhere(sim.cell_classes() >= hf.CELL_BOUNDARY).mean(axis=0), first + (2, 0, 0))
    np.testing.assert_allclose(sim.probe["transform"], turn)
    np.testing.assert_allclose(sim.probe["velocity"], (0, 0, 0))

    # Loose vertices (used by no triangle) do not count for the bounds.
    loose = np.vstack([vertices, [[50.0, 50.0, 50.0]]]).astype(np.float32)
    sim.set_mesh_probe(loose, triangles, moved(0.5, 0.5, 0.5))
    assert sim.probe["vertex_count"] == 9

    # A given torque centre is reported back.
    sim.set_mesh_probe(vertices, triangles, moved(0.5, 0.5, 0.5), torque_centre=(0.1, 0.2, 0.3))
    np.testing.assert_allclose(sim.probe["torque_centre"], (0.1, 0.2, 0.3))
    np.testing.assert_allclose(sim.step(0.01).torque_centre, (0.1, 0.2, 0.3), atol=1e-6)


def test_probe_pose_moves_a_sphere(sim):
    sim.set_probe((0.5, 0.5, 0.5), 0.15)
    sim.set_probe_pose(moved(0.45, 0.55, 0.5), velocity=(0.2, 0, 0), angular_velocity=(0, 1.0, 0))
    probe = sim.probe
    assert probe["kind"] == "sphere"
    np.testing.assert_allclose(probe["centre"], (0.45, 0.55, 0.5))
    assert probe["radius"] == pytest.approx(0.15)
    np.testing.assert_allclose(probe["velocity"], (0.2, 0, 0))
    np.testing.assert_allclose(probe["angular_velocity"], (0, 1.0, 0))
    report = sim.step(0.01)
    np.testing.assert_allclose(report.torque_centre, (0.45, 0.55, 0.5), atol=0.5 * sim.cell_size)
    sim.clear_probe()
    assert sim.probe is None
    assert sim.step(0.01).solid_cells == 0
    with pytest.raises(hf.InvalidArgumentError, match="no probe"):
        sim.set_probe_pose(moved(0.5, 0.5, 0.5))


def _open_box():
    v, t = meshes.box((0.2, 0.2, 0.2))
    return v, t[:-1]


def _flipped_box():
    v, t = meshes.box((0.2, 0.2, 0.2))
    t = t.copy()
    t[0] = t[0][::-1]
    return v, t


@pytest.mark.parametrize(
    "make, kwargs, words",
    [
        (lambda: (np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32)), {}, "empty"),
        (lambda: (np.zeros((8, 2), np.float32), meshes.box((0.2, 0.2, 0.2))[1]), {}, r"vertices must be .* \(N, 3\)"),
        (lambda: (meshes.box((0.2, 0.2, 0.2))[0], meshes.box((0.2, 0.2, 0.2))[1].astype(np.float32)), {},
         "triangles must be an integer array"),
        (lambda: (meshes.box((0.2, 0.2, 0.2))[0], meshes.box((0.2, 0.2, 0.2))[1].ravel()), {}, r"shape \(M, 3\)"),
        (lambda: (meshes.box((0.2, 0.2, 0.2))[0], meshes.box((0.2, 0.2, 0.2))[1] + 1), {}, "vertex index 8"),
        (lambda: (meshes.box((0.2, 0.2, 0.2))[0], -meshes.box((0.2, 0.2, 0.2))[1]), {}, "vertex index -"),
        (lambda: (meshes.box((0.2, 0.2, 0.2))[0] * np.float32(np.nan), meshes.box((0.2, 0.2, 0.2))[1]), {}, "not finite"),
        (_open_box, {}, "not closed"),
        (_flipped_box, {}, "consistently oriented"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": None}, "not inside the domain"),  # centred on a corner
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": moved(0.15, 0.5, 0.5)}, "one cell"),  # touches the margin
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": moved(5.0, 0.5, 0.5)}, "within"),
        (lambda: meshes.box((0.9, 0.2, 0.2)), {"transform": moved(0.5, 0.5, 0.5)}, "scale it down"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": np.eye(3)}, "4x4"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": "identity"}, "4x4"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": np.zeros((4, 4))}, "affine"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": np.diag([1.0, 0.0, 1.0, 1.0])}, "singular"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": moved(0.5, math.nan, 0.5)}, "finite"),
        (lambda: meshes.box((0.2, 0.2, 0.2)), {"transform": moved(0.5, 0.5, 0.5), "velocity": (1e9, 0, 0)}, "speed"),
        (lambda: meshes.box((0.2, 0.2, 0.2)),
         {"transform": moved(0.5, 0.5, 0.5), "angular_velocity": (0, math.inf, 0)}, "finite"),
        (lambda: meshes.box((0.2, 0.2, 0.2)),
         {"transform": moved(0.5, 0.5, 0.5), "torque_centre": (0, math.nan, 0)}, "torque centre"),
    ],
)
def test_bad_mesh_probe_is_explained_and_changes_nothing(sim, make, kwargs, words):
    sim.set_probe((0.5, 0.5, 0.5), 0.2)
    vertices, triangles = make()
    with pytest.raises(hf.InvalidArgumentError, match=words):
        sim.set_mesh_probe(vertices, triangles, **kwargs)
    assert sim.probe["kind"] == "sphere" and sim.probe["radius"] == pytest.approx(0.2)


def test_bad_probe_pose_is_explained_and_changes_nothing(sim):
    vertices, triangles = meshes.box((0.3, 0.2, 0.25))
    sim.set_mesh_probe(vertices, triangles, moved(0.5, 0.5, 0.5))
    for transform, words in [
        (moved(0.9, 0.5, 0.5), "not inside the domain"),
        (np.diag([3.0, 1.0, 1.0, 1.0]) @ moved(0.5, 0.5, 0.5), "not inside the domain"),
        (np.zeros((4, 4)), "affine"),
        (moved(math.inf, 0.5, 0.5), "finite"),
        ([[1, 0, 0], [0, 1, 0]], "4x4"),
    ]:
        with pytest.raises(hf.InvalidArgumentError, match=words):
            sim.set_probe_pose(transform)
    with pytest.raises(hf.InvalidArgumentError, match="speed"):
        sim.set_probe_pose(moved(0.5, 0.5, 0.5), velocity=(1e9, 0, 0))
    np.testing.assert_allclose(sim.probe["transform"], moved(0.5, 0.5, 0.5))
    sim.set_probe((0.5, 0.5, 0.5), 0.2)
    with pytest.raises(hf.InvalidArgumentError, match="not inside the domain"):
        sim.set_probe_pose(moved(0.1, 0.5, 0.5))
    np.testing.assert_allclose(sim.probe["centre"], (0.5, 0.5, 0.5))


def test_probe_pose_does_not_wait_for_a_running_step():
    """A haptic loop or bake driver moves the mesh while a long GPU step runs; the next step
    takes the latest pose."""
    sim = hf.Simulation(resolution=(32, 32, 32), pressure_iterations=1000, gravity=(0, 0, 0))
    vertices, triangles = meshes.icosphere(2, 0.15)
    sim.set_mesh_probe(vertices, triangles, moved(0.5, 0.5, 0.5))
    sim.step(0.01)
    with step_in_background(sim, 0.01) as done:
        for i in range(200):
            sim.set_probe_pose(moved(0.5 + 0.0005 * i, 0.5, 0.5), velocity=(0.05, 0, 0))
        finished_during_poses = done.is_set()
    assert not finished_during_poses
    np.testing.assert_allclose(sim.probe["transform"], moved(0.5 + 0.0005 * 199, 0.5, 0.5), atol=1e-6)
    sim.pressure_iterations = 1
    report = sim.step(0.01)
    assert report.torque_centre[0] == pytest.approx(0.5995, abs=0.5 * sim.cell_size)
    sim.close()
