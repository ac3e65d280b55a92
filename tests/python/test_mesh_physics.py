# SPDX-License-Identifier: GPL-3.0-or-later
"""Known answers for mesh probes: Archimedes for a sphere mesh and a rotated box, no sideways
force or torque on a symmetric body moving along an axis, a resisting torque on a paddle
turning in still water (sized for llvmpipe on 2 cores)."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes

G = 9.81


def pose(translation, axis=(0.0, 0.0, 1.0), angle=0.0):
    """4x4 matrix_world: rotation by `angle` (rad) about `axis`, then `translation` (m)."""
    n = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)
    m[:3, 3] = translation
    return m


def test_archimedes_sphere_mesh_at_64():
    """An icosphere (5120 triangles) at rest in still water feels rho g (4/3 pi r^3) upward,
    acting at its centre: no torque about the voxelized centroid."""
    rho, radius = 1000.0, 0.2
    vertices, triangles = meshes.icosphere(4, radius)
    sim = hf.Simulation(resolution=(64, 64, 64), fluid_density=rho, pressure_iterations=2)
    sim.set_mesh_probe(vertices, triangles, pose((0.5, 0.5, 0.5)))
    report = sim.step(0.01)
    expected = rho * G * 4.0 / 3.0 * np.pi * radius**3
    fx, fy, fz = report.force
    assert fz == pytest.approx(expected, rel=0.02)
    assert abs(fx) < 1e-3 * expected and abs(fy) < 1e-3 * expected
    assert report.solid_cells * sim.cell_size**3 == pytest.approx(4.0 / 3.0 * np.pi * radius**3, rel=0.02)
    np.testing.assert_allclose(report.torque_centre, (0.5, 0.5, 0.5), atol=0.5 * sim.cell_size)
    assert np.linalg.norm(report.torque) < 1e-3 * expected * radius


def test_archimedes_rotated_box_at_64():
    """A box turned about a skew axis: rho g V upward (V = a b c), acting at its centroid; the
    torque about another point c is (centroid - c) x F."""
    rho, size = 1000.0, (0.36, 0.22, 0.28)
    volume = size[0] * size[1] * size[2]
    vertices, triangles = meshes.box(size)
    centre = (0.48, 0.52, 0.5)
    sim = hf.Simulation(resolution=(64, 64, 64), fluid_density=rho, pressure_iterations=2)
    sim.set_mesh_probe(vertices, triangles, pose(centre, axis=(1.0, 2.0, 3.0), angle=0.7))
    report = sim.step(0.01)
    expected = rho * G * volume
    fx, fy, fz = report.force
    assert fz == pytest.approx(expected, rel=0.02)
    assert abs(fx) < 1e-3 * expected and abs(fy) < 1e-3 * expected
    centroid = report.torque_centre
    np.testing.assert_allclose(centroid, centre, atol=0.5 * sim.cell_size)
    assert np.linalg.norm(report.torque) < 1e-3 * expected * max(size)

    point = np.array([0.3, 0.45, 0.6])
    sim.set_mesh_probe(vertices, triangles, pose(centre, axis=(1.0, 2.0, 3.0), angle=0.7), torque_centre=point)
    moved = sim.step(0.01)
    np.testing.assert_allclose(moved.torque_centre, point, atol=1e-6)
    want = np.cross(centroid - point, moved.force)
    np.testing.assert_allclose(moved.torque, want, atol=1e-3 * np.linalg.norm(want))


def test_symmetric_mesh_moving_along_an_axis():
    """An icosphere pushed along +x through still fluid: the force resists the motion, with
    almost no sideways part and almost no torque. It is turned and placed off the grid's
    symmetry planes, so its voxels are not mirror-symmetric and the answers are not exact zeros."""
    sim = hf.Simulation(resolution=(32, 32, 32), fluid_density=1000.0, gravity=(0, 0, 0), pressure_iterations=40)
    vertices, triangles = meshes.icosphere(3, 0.2)
    speed, dt = 0.5, 0.02
    at = lambda i: pose((0.45 + speed * dt * i, 0.513, 0.487), axis=(1.0, 1.0, 1.0), angle=0.5)  # noqa: E731
    sim.set_mesh_probe(vertices, triangles, at(0), velocity=(speed, 0, 0))
    for i in range(3):
        sim.set_probe_pose(at(i), velocity=(speed, 0, 0))
        report = sim.step(dt)
        fx, fy, fz = report.force
        assert fx < 0, report.force
        assert abs(fy) < 0.02 * abs(fx) and abs(fz) < 0.02 * abs(fx), report.force
        assert np.linalg.norm(report.torque) < 0.01 * abs(fx) * 0.2, (report.torque, report.force)


def test_rotating_paddle_feels_a_resisting_torque():
    """A thin box turning about z in still water: the fluid's torque opposes the spin, about z
    only, with no net force (the paddle is symmetric about its axis)."""
    sim = hf.Simulation(resolution=(48, 48, 48), fluid_density=1000.0, gravity=(0, 0, 0), pressure_iterations=40)
    vertices, triangles = meshes.box((0.5, 0.09, 0.4))
    omega, dt = np.array([0.0, 0.0, 4.0]), 0.01
    sim.set_mesh_probe(vertices, triangles, pose((0.5, 0.5, 0.5)), angular_velocity=omega)
    for i in range(3):
        sim.set_probe_pose(pose((0.5, 0.5, 0.5), angle=omega[2] * dt * i), angular_velocity=omega)
        report = sim.step(dt)
        tx, ty, tz = report.torque
        assert tz < 0, report.torque
        assert abs(tx) < 0.05 * abs(tz) and abs(ty) < 0.05 * abs(tz), report.torque
        assert np.linalg.norm(report.force) * 0.25 < 0.05 * abs(tz), (report.force, report.torque)
