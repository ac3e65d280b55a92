# SPDX-License-Identifier: GPL-3.0-or-later
"""Known answers of the multigrid pressure solver (pressure_solver='multigrid'), sized for
llvmpipe on 2 cores: the discrete divergence after a converged solve, the added mass of a
sphere started from rest against potential flow, and its convergence with resolution."""

import math

import numpy as np
import pytest

import hapticfluid as hf
from conftest import max_divergence

RHO = 1000.0  # kg/m^3
SPEED = 0.5  # m/s
DT = 0.01  # s


def _multigrid_sim(n, **kwargs):
    kwargs.setdefault("pressure_tolerance", 1e-5)
    kwargs.setdefault("pressure_iterations", 100)
    return hf.Simulation(resolution=(n, n, n), gravity=(0, 0, 0), fluid_density=RHO, pressure_solver="multigrid",
                         **kwargs)


@pytest.mark.parametrize("open_top", [False, True], ids=["closed", "open_top"])
def test_divergence_after_a_multigrid_solve_is_negligible(open_top):
    """max |div u| dx / |u| <= 1e-4 after one projection of a sphere moving up and sideways."""
    sim = _multigrid_sim(32, open_top=open_top)
    sphere = ((0.47, 0.5, 0.55), 0.2, (SPEED, 0.0, 0.3 * SPEED))
    sim.set_probe(sphere[0], sphere[1], velocity=sphere[2])
    report = sim.step(DT)
    assert report.relative_residual <= 1e-5 * 1.5, report
    assert 0 < report.pressure_iterations < 100, report
    # cut cells (the default): the flux w u + (1 - w) u_sphere through each face
    div = max_divergence(sim, sphere) / SPEED  # |sum of outgoing face velocities| / |u| = |div u| h / |u|
    assert div <= 1e-4, f"max |div u| dx / |u| = {div:.3g}"


def _added_mass_coefficient(n, radius):
    """C_m = -F dt / (rho V v) of the first step of a sphere started from rest (V of its voxels)."""
    sim = _multigrid_sim(n)
    sim.set_probe((0.5, 0.5, 0.5), radius, velocity=(SPEED, 0.0, 0.0))
    report = sim.step(DT)
    solid = np.count_nonzero(sim.cell_classes() >= hf.CELL_BOUNDARY)
    volume = solid * sim.cell_size**3
    sim.close()
    fx = float(report.force[0])
    return -fx * DT / (RHO * volume * SPEED), fx, volume, report


def confined_sphere_added_mass(sphere_radius, box_volume):
    """Added-mass coefficient of a sphere of radius a inside a concentric fixed spherical wall of
    radius R: C = (1/2) (R^3 + 2 a^3) / (R^3 - a^3) = 0.5 (1 + 2 q^3) / (1 - q^3), q = a / R
    (Lamb, Hydrodynamics, 6th ed. 1932, sec. 92; C -> 1/2 in unbounded fluid). The box is
    replaced by the sphere of equal volume, R = (3 V_box / (4 pi))^(1/3)."""
    outer = (3.0 * box_volume / (4.0 * math.pi)) ** (1.0 / 3.0)
    q3 = (sphere_radius / outer) ** 3
    return 0.5 * (1.0 + 2.0 * q3) / (1.0 - q3)


def test_added_mass_of_a_sphere_converges_to_potential_flow():
    """The impulse of the first step of a sphere (radius 0.2 m, 1 m box, water, 0.5 m/s) gives the
    added-mass coefficient of potential flow, confined by the box, within 15% at 32^3, 48^3
    and 64^3; the coefficient's changes shrink as the grid is refined."""
    radius = 0.2
    rows = []
    for n in (32, 48, 64):
        cm, fx, volume, report = _added_mass_coefficient(n, radius)
        # The voxel body's own radius (its volume's sphere) sets the confinement.
        voxel_radius = (3.0 * volume / (4.0 * math.pi)) ** (1.0 / 3.0)
        expected = confined_sphere_added_mass(voxel_radius, 1.0)
        rows.append((n, fx, cm, expected, report.pressure_iterations, report.relative_residual))
    table = "\n".join(["  n   force_x (N)   C_m     C_m analytic  CG its  residual"] +
                      [f"{n:3d}  {fx:11.3f}  {cm:.4f}   {ex:.4f}       {it:3d}   {res:.2e}"
                       for n, fx, cm, ex, it, res in rows])
    print("\nadded mass against resolution (multigrid, tolerance 1e-5):\n" + table)
    for n, _, cm, expected, _, res in rows:
        assert res <= 1.5e-5, table
        assert cm == pytest.approx(expected, rel=0.15), f"{n}^3:\n{table}"
    c32, c48, c64 = (r[2] for r in rows)
    assert abs(c64 - c48) < abs(c48 - c32), f"no convergence with resolution:\n{table}"


def test_multigrid_settings_and_report():
    sim = hf.Simulation(resolution=(16, 16, 16), gravity=(0, 0, 0))
    assert sim.pressure_solver == hf.PressureSolver.jacobi and sim.pressure_tolerance == 0.0  # the defaults
    sim.pressure_solver = "multigrid"  # a member's name stands for it
    sim.pressure_tolerance = 1e-4
    sim.pressure_iterations = 50
    sim.set_probe((0.5, 0.5, 0.5), 0.2, velocity=(SPEED, 0, 0))
    report = sim.step(DT)
    assert sim.pressure_solver == hf.PressureSolver.multigrid
    assert sim.pressure_tolerance == pytest.approx(1e-4)
    assert 0 < report.pressure_iterations < 50
    assert report.relative_residual <= 1.5e-4
    assert report.initial_relative_residual == pytest.approx(1.0, rel=1e-3)  # from rest: p = 0, r = rhs
    # Fixed-count mode runs exactly pressure_iterations and measures no starting residual.
    sim.pressure_tolerance = 0.0
    sim.pressure_iterations = 3
    report = sim.step(DT)
    assert report.pressure_iterations == 3 and report.initial_relative_residual == -1.0
    # Without compute_residual the solver's own estimate is reported in tolerance mode.
    sim.compute_residual = False
    sim.pressure_tolerance = 1e-3
    sim.pressure_iterations = 40
    report = sim.step(DT)
    assert 0.0 <= report.relative_residual <= 1e-3


@pytest.mark.parametrize("name, value, message", [
    ("pressure_solver", "sor", "pressure_solver must be one of 'jacobi', 'multigrid'"),
    ("pressure_tolerance", -1e-3, "pressure tolerance"),
    ("pressure_tolerance", 1.0, "pressure tolerance"),
    ("pressure_tolerance", 1e-9, "pressure tolerance"),
    ("pressure_tolerance", float("nan"), "pressure tolerance"),
])
def test_bad_multigrid_settings_are_rejected(small_sim, name, value, message):
    before = (small_sim.pressure_solver, small_sim.pressure_tolerance)
    with pytest.raises(hf.InvalidArgumentError, match=message):
        setattr(small_sim, name, value)
    with pytest.raises(hf.InvalidArgumentError, match=message):
        hf.Simulation(resolution=(8, 8, 8), **{name: value})
    assert (small_sim.pressure_solver, small_sim.pressure_tolerance) == before
