# SPDX-License-Identifier: GPL-3.0-or-later
"""A host device that carries an orientation turns a HapticSession's mesh probe: the probe the
session places (rotation from the pushed quaternion, scale from the start, angular velocity from
successive pushes) is the probe a bake-like set_probe_pose of the same matrix gives, cell for cell
and in force and torque."""

import math

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes

RES = 20
SCALE = np.diag([1.25, 1.0, 0.8])  # the probe's own (non-uniform) scale, kept from the start
CENTRE = np.array([0.5, 0.5, 0.5])


def rotation(axis, angle):
    a = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def quaternion(axis, angle):
    a = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    return (math.cos(angle / 2), *(math.sin(angle / 2) * a))


def matrix(rot, centre=CENTRE):
    m = np.eye(4)
    m[:3, :3] = rot @ SCALE
    m[:3, 3] = centre
    return m


def new_sim():
    return hf.Simulation(resolution=(RES, RES, RES), pressure_iterations=30, fluid_density=1000.0,
                         gravity=(0.0, 0.0, 0.0))


def session_for(sim, host):
    # Identity map (device frame = world), fixed steps, no real-time priority: what the add-on's
    # Mouse mode does, made deterministic.
    return hf.HapticSession(sim, host, workspace_scale=1.0, workspace_offset=(0.0, 0.0, 0.0), probe_radius=None,
                            sim_dt=0.01, realtime=False)


def wait_steps(session, n, timeout=60.0):
    import time

    end = time.monotonic() + timeout
    while session.stats()["sim_steps"] < n and time.monotonic() < end:
        time.sleep(0.01)
    assert session.stats()["sim_steps"] >= n


def test_turned_probe_matches_a_bake_like_pose():
    vertices, triangles = meshes.box((0.3, 0.16, 0.1))
    axis, angle0, angle1, dt = (0.3, 0.2, 1.0), 0.2, 0.7, 0.1
    spin = np.asarray(axis) / np.linalg.norm(axis) * (angle1 - angle0) / dt  # rad/s, world frame
    with new_sim() as a, new_sim() as b:
        a.set_mesh_probe(vertices, triangles, matrix(np.eye(3)))  # starts unturned
        host = hf.host_device(extrapolate=False)
        host.push_pose(tuple(CENTRE), time=0.0, orientation=quaternion(axis, angle0))
        host.push_pose(tuple(CENTRE), time=dt, orientation=quaternion(axis, angle1))
        session = session_for(a, host)
        session.start()
        wait_steps(session, 3)
        session.stop()
        expected = matrix(rotation(axis, angle1))
        probe = a.probe
        np.testing.assert_allclose(probe["transform"], expected, atol=2e-6)
        np.testing.assert_allclose(probe["angular_velocity"], spin, rtol=1e-4)
        np.testing.assert_allclose(probe["velocity"], 0.0, atol=1e-6)

        # The same pose given as a bake gives it: cells, force and torque agree from the same start.
        b.set_mesh_probe(vertices, triangles, expected, angular_velocity=tuple(spin))
        a.reset()
        ra, rb = a.step(0.01), b.step(0.01)
        np.testing.assert_array_equal(a.cell_classes(), b.cell_classes())
        assert ra.solid_cells == rb.solid_cells and ra.exposed_faces == rb.exposed_faces
        # The spinning box's net force is zero: what is left is the rounding of pressure forces of
        # about |torque| / 0.05 m (~100 N) cancelling over its faces; float keeps 6e-8 of them.
        rounding = 6e-8 * float(np.linalg.norm(rb.torque)) / 0.05
        np.testing.assert_allclose(ra.force, rb.force, rtol=1e-4, atol=rounding)
        np.testing.assert_allclose(ra.torque, rb.torque, rtol=1e-4, atol=1e-6)
        # ... and the turn is real: the spinning box feels a torque against its spin, and the
        # unturned box covers other cells.
        assert float(np.dot(ra.torque, spin)) < 0.0, (ra.torque, spin)
        b.set_probe_pose(matrix(np.eye(3)))
        b.step(0.01)
        assert np.any(a.cell_classes() != b.cell_classes())


def test_a_three_dof_device_keeps_the_starting_rotation():
    vertices, triangles = meshes.box((0.3, 0.16, 0.1))
    start = matrix(rotation((0, 0, 1), 0.4))
    with new_sim() as a:
        a.set_mesh_probe(vertices, triangles, start)
        host = hf.host_device(extrapolate=False)
        host.push_pose((0.45, 0.5, 0.5), time=0.0)  # no orientation: a position only
        session = session_for(a, host)
        session.start()
        wait_steps(session, 2)
        session.stop()
        moved = start.copy()
        moved[:3, 3] = (0.45, 0.5, 0.5)
        np.testing.assert_allclose(a.probe["transform"], moved, atol=2e-6)
        np.testing.assert_allclose(a.probe["angular_velocity"], 0.0, atol=0.0)


def test_a_turn_that_cannot_fit_keeps_the_starting_rotation():
    # A bar 0.75 m long (0.6 m x scale 1.25) lies along x in a domain 0.5 m high: stood up by a
    # quarter turn about y it would reach through the floor and the lid, so the session keeps
    # the starting rotation (and the session goes on) rather than hand the simulation a pose it
    # refuses.
    vertices, triangles = meshes.box((0.6, 0.1, 0.1))
    centre = (0.5, 0.5, 0.25)
    with hf.Simulation(resolution=(20, 20, 10), domain_size=(1.0, 1.0, 0.5), pressure_iterations=30,
                       fluid_density=1000.0, gravity=(0.0, 0.0, 0.0)) as a:
        a.set_mesh_probe(vertices, triangles, matrix(np.eye(3), centre))
        host = hf.host_device(extrapolate=False)
        host.push_pose(centre, time=0.0, orientation=quaternion((0, 1, 0), math.pi / 2))
        session = session_for(a, host)
        session.start()
        wait_steps(session, 2)
        session.stop()
        assert session.error is None
        np.testing.assert_allclose(a.probe["transform"], matrix(np.eye(3), centre), atol=2e-6)


def test_host_device_orientation_and_spin():
    host = hf.host_device()
    host.push_pose((0.0, 0.0, 0.0), time=1.0, orientation=(2.0, 0.0, 0.0, 0.0))  # normalised here
    host.push_pose((0.0, 0.0, 0.0), time=1.5, orientation=quaternion((0, 0, 1), 0.2))
    s = host.state_after(0.05)  # turned on along the spin, as the position is carried along
    np.testing.assert_allclose(s.angular_velocity, (0.0, 0.0, 0.4), rtol=1e-5)
    np.testing.assert_allclose(s.orientation, quaternion((0, 0, 1), 0.22), atol=1e-6)
    # ... for at most one push interval and 0.1 s (as the position)
    np.testing.assert_allclose(host.state_after(10.0).orientation, quaternion((0, 0, 1), 0.24), atol=1e-6)
    # The shortest arc: -q is the same rotation, so no spin.
    host.push_pose((0.0, 0.0, 0.0), time=2.0, orientation=tuple(-c for c in quaternion((0, 0, 1), 0.2)))
    np.testing.assert_allclose(host.state_after(0.0).angular_velocity, 0.0, atol=1e-6)
    assert hf.host_device().state_after(0.0).orientation is None
    host.push_pose((0.0, 0.0, 0.0), time=3.0)  # a position only: 3-DoF again
    assert host.state_after(0.0).orientation is None


@pytest.mark.parametrize("bad", [(0.0, 0.0, 0.0, 0.0), (math.nan, 0.0, 0.0, 1.0), (math.inf, 0.0, 0.0, 0.0)])
def test_bad_orientation_names_it(bad):
    host = hf.host_device()
    with pytest.raises(hf.InvalidArgumentError, match="orientation"):
        host.push_pose((0.0, 0.0, 0.0), orientation=bad)


@pytest.mark.parametrize("mirror", [1.0, -1.0], ids=["proper", "mirrored"])
def test_the_engines_probe_rotation_turns_the_probe_to_the_pushed_matrix(mirror):
    """What the add-on's Mouse mode does each tick: push HapticSession.probe_rotation of the
    object's matrix (scaled, turned, perhaps mirrored) as the orientation; the session then puts
    the probe at that very matrix (its scale kept from the start)."""
    vertices, triangles = meshes.box((0.3, 0.16, 0.1))
    flip = np.diag([1.0, 1.0, mirror])
    start = matrix(rotation((0, 0, 1), 0.4) @ flip)
    turned = matrix(rotation((0.3, 0.2, 1.0), 0.9) @ flip)
    q = hf.HapticSession.probe_rotation(turned)
    assert len(q) == 4 and abs(np.linalg.norm(q) - 1.0) < 1e-6
    with new_sim() as a:
        a.set_mesh_probe(vertices, triangles, start)
        host = hf.host_device(extrapolate=False)
        host.push_pose(tuple(turned[:3, 3]), time=0.0, orientation=q)
        session = session_for(a, host)
        session.start()
        wait_steps(session, 2)
        session.stop()
        np.testing.assert_allclose(a.probe["transform"], turned, atol=2e-6)
    with pytest.raises(hf.InvalidArgumentError, match="transform"):
        hf.HapticSession.probe_rotation(np.eye(3))
