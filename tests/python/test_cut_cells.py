# SPDX-License-Identifier: GPL-3.0-or-later
"""Known answers of cut cells (Simulation.cut_cells: the sphere probe's ramp fractions, the mesh
probe's fine control-volume fractions)."""

import math

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes
from hapticfluid.bench.force_roughness import roughness

RHO = 1000.0
G = 9.81


def test_cut_cells_are_on_by_default():
    sim = hf.Simulation(resolution=(8, 8, 8))
    assert sim.cut_cells is True
    sim.cut_cells = False
    assert sim.cut_cells is False


def test_archimedes_with_cut_cells_matches_the_analytic_sphere():
    """At rest in still water the cut-cell sphere (radius 0.2 m, 40^3) feels rho g (4/3 pi r^3) up
    within 0.5% (the voxel body's volume is off by more), and no sideways force."""
    radius = 0.2
    sim = hf.Simulation(resolution=(40, 40, 40), fluid_density=RHO, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=100)
    sim.cut_cells = True
    sim.set_probe((0.503, 0.49, 0.511), radius)
    fx, fy, fz = sim.step(0.01).force
    expected = RHO * G * 4.0 / 3.0 * math.pi * radius**3
    assert fz == pytest.approx(expected, rel=0.005)
    assert abs(fx) < 1e-3 * expected and abs(fy) < 1e-3 * expected


def _forces(cut_cells, n=24, steps=40):
    sim = hf.Simulation(resolution=(n, n, n), gravity=(0, 0, 0), fluid_density=RHO, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=100)
    sim.cut_cells = cut_cells
    dt, speed = 1.0 / 120.0, 0.25
    out = []
    for i in range(steps):
        sim.set_probe((0.3 + speed * dt * (i + 1), 0.5, 0.5), 0.09, velocity=(speed, 0, 0))
        out.append(sim.step(dt).force)
    sim.close()
    return out[steps // 3:]


def test_cut_cells_make_the_force_smoother_and_keep_it_axial():
    binary = roughness([f[0] for f in _forces(False)])
    cut_forces = _forces(True)
    cut = roughness([f[0] for f in cut_forces])
    assert cut["mean"] < 0 and binary["mean"] < 0  # resisted
    # At this 24^3 grid the cut-cell force's roughness measures 0.127 (binary 1.86); the goal of
    # 0.05 is met at 48^3 (bench force_roughness: 0.012). 0.2 fails a regression to 0.3, which
    # the old bound (half the binary roughness) let through.
    assert cut["roughness"] < 0.2 and cut["roughness"] < 0.1 * binary["roughness"], (cut, binary)
    assert cut["largest_jump"] < 0.5 * binary["largest_jump"], (cut, binary)
    for fx, fy, fz in cut_forces:
        assert abs(fy) < 0.01 * abs(cut["mean"]) and abs(fz) < 0.01 * abs(cut["mean"])


def test_added_mass_with_cut_cells_is_within_three_percent_of_lamb_at_64():
    """The impulse of the first step of a cut-cell sphere (radius 0.2 m, 1 m box of water, 0.5 m/s,
    64^3) gives the added-mass coefficient of a sphere in a concentric spherical wall of the box's
    volume within 3% (voxels: 6-7% high); no sideways force."""
    from test_multigrid_physics import confined_sphere_added_mass

    radius, speed, dt = 0.2, 0.5, 0.01
    sim = hf.Simulation(resolution=(64, 64, 64), gravity=(0, 0, 0), fluid_density=RHO, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=100)
    sim.cut_cells = True
    sim.set_probe((0.5, 0.5, 0.5), radius, velocity=(speed, 0.0, 0.0))
    fx, fy, fz = sim.step(dt).force
    sim.close()
    volume = 4.0 / 3.0 * math.pi * radius**3
    cm = -fx * dt / (RHO * volume * speed)
    assert cm == pytest.approx(confined_sphere_added_mass(radius, 1.0), rel=0.03)
    assert abs(fy) < 1e-3 * abs(fx) and abs(fz) < 1e-3 * abs(fx)


def _translation(centre):
    m = np.eye(4)
    m[:3, 3] = centre
    return m


def _polyhedron_volume(vertices, triangles):
    v = np.asarray(vertices, dtype=float)
    t = np.asarray(triangles)
    return abs(np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum()) / 6.0


def test_mesh_sphere_with_cut_cells_matches_the_analytic_sphere_at_40():
    """An icosphere (1280 triangles, r 0.2 m) with cut cells at 40^3: Archimedes within 0.5% of
    rho g V (V the polyhedron's volume), and the first step's impulse gives the confined
    sphere's added mass within 3% (voxels: 11% high at this size), with no sideways force."""
    from test_multigrid_physics import confined_sphere_added_mass

    radius, speed, dt = 0.2, 0.5, 0.01
    vertices, triangles = meshes.icosphere(3, radius)
    volume = _polyhedron_volume(vertices, triangles)
    sim = hf.Simulation(resolution=(40, 40, 40), fluid_density=RHO, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=100)
    assert sim.cut_cells
    sim.set_mesh_probe(vertices, triangles, _translation((0.503, 0.49, 0.511)))
    fx, fy, fz = sim.step(0.01).force
    sim.close()
    assert fz == pytest.approx(RHO * G * volume, rel=0.005)
    assert abs(fx) < 1e-3 * fz and abs(fy) < 1e-3 * fz

    sim = hf.Simulation(resolution=(40, 40, 40), gravity=(0, 0, 0), fluid_density=RHO, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=100)
    sim.set_mesh_probe(vertices, triangles, _translation((0.5, 0.5, 0.5)), velocity=(speed, 0.0, 0.0))
    fx, fy, fz = sim.step(dt).force
    sim.close()
    cm = -fx * dt / (RHO * volume * speed)
    assert cm == pytest.approx(confined_sphere_added_mass(radius, 1.0), rel=0.03)
    assert abs(fy) < 1e-3 * abs(fx) and abs(fz) < 1e-3 * abs(fx)
