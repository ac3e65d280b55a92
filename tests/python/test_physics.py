# SPDX-License-Identifier: GPL-3.0-or-later
"""Known answers of the solver (sized for llvmpipe on 2 cores)."""

import numpy as np
import pytest

import hapticfluid as hf
from conftest import max_divergence

G = 9.81


def sphere_cell_counts(res, h, centre, radius):
    """Analytic reference: classes of a sphere voxelized by cell centre, from the 6-neighbour rule."""
    idx = [(np.arange(n) + 0.5) * h for n in res]
    x, y, z = np.meshgrid(*idx, indexing="ij")
    solid = (x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2 <= radius**2
    padded = np.pad(solid, 1, constant_values=False)
    fluid_nb = np.zeros_like(solid)
    solid_nb = np.zeros_like(solid)
    inner = (slice(1, -1),) * 3
    for axis in range(3):
        for shift in (-1, 1):
            nb = np.roll(padded, shift, axis=axis)[inner]
            in_grid = np.roll(np.pad(np.ones_like(solid), 1, constant_values=False), shift, axis=axis)[inner]
            fluid_nb |= in_grid & ~nb
            solid_nb |= nb
    return {
        hf.CELL_INSIDE: int((solid & ~fluid_nb).sum()),
        hf.CELL_BOUNDARY: int((solid & fluid_nb).sum()),
        hf.CELL_SURROUNDING: int((~solid & solid_nb).sum()),
        hf.CELL_OUTSIDE: int((~solid & ~solid_nb).sum()),
    }


def test_divergence_after_projection_falls_with_iterations():
    """max |div u| after one projection of a moving sphere's displacement, for more and more sweeps
    (with cut cells, the divergence of the faces' fluid-plus-solid fluxes)."""
    speed = 1.0
    measured = []
    for iterations in (10, 60, 400):
        sim = hf.Simulation(resolution=(32, 32, 32), gravity=(0, 0, 0), pressure_iterations=iterations)
        sim.set_probe((0.5, 0.5, 0.5), 0.15, velocity=(speed, 0, 0))
        report = sim.step(0.01)
        # cut cells (the default): the flux w u + (1 - w) u_sphere through each face
        measured.append((max_divergence(sim, ((0.5, 0.5, 0.5), 0.15, (speed, 0, 0))) / speed,
                         report.relative_residual))
    divs = [d for d, _ in measured]
    residuals = [r for _, r in measured]
    assert divs[0] > divs[1] > divs[2], measured
    assert residuals[0] > residuals[1] > residuals[2], measured
    assert divs[2] < 0.01, measured  # |div u| h / |u| after 400 sweeps
    assert divs[0] > 10 * divs[2], measured


def test_archimedes_buoyancy_at_64():
    """A sphere at rest in still water under gravity feels rho g V upward, V of its voxels."""
    rho = 1000.0
    radius = 0.2
    sim = hf.Simulation(resolution=(64, 64, 64), fluid_density=rho, pressure_iterations=2)
    sim.set_probe((0.5, 0.5, 0.5), radius)
    report = sim.step(0.01)
    classes = sim.cell_classes()
    volume_voxels = np.count_nonzero(classes >= hf.CELL_BOUNDARY) * sim.cell_size**3
    expected = rho * G * volume_voxels
    fx, fy, fz = report.force
    assert fz == pytest.approx(expected, rel=0.01)
    assert abs(fx) < 1e-3 * expected and abs(fy) < 1e-3 * expected
    # The voxel body converges to the analytic sphere: within 2% at 64^3.
    assert fz == pytest.approx(rho * G * 4.0 / 3.0 * np.pi * radius**3, rel=0.02)


def test_buoyancy_scales_with_gravity_and_density():
    sim = hf.Simulation(resolution=(32, 32, 32), fluid_density=500.0, gravity=(0, 0, -2.0), pressure_iterations=2)
    sim.set_probe((0.5, 0.5, 0.5), 0.2)
    f1 = sim.step(0.01).force[2]
    sim.gravity = (0.0, 0.0, -4.0)
    sim.fluid_density = 250.0
    f2 = sim.step(0.01).force[2]
    assert f1 > 0
    assert f2 == pytest.approx(f1, rel=1e-4)
    sim.gravity = (0.0, 0.0, 0.0)
    assert abs(sim.step(0.01).force[2]) < 1e-6 * f1


def test_moving_sphere_is_resisted_without_sideways_force():
    """A sphere pushed along +x through still fluid (no gravity) feels -x; y and z stay under 5%."""
    sim = hf.Simulation(resolution=(48, 32, 32), domain_size=(1.5, 1.0, 1.0), gravity=(0, 0, 0),
                        pressure_iterations=80)
    speed, dt, radius = 0.5, 0.02, 0.12
    forces = []
    for i in range(8):
        x = 0.4 + speed * dt * i
        sim.set_probe((x, 0.5, 0.5), radius, velocity=(speed, 0, 0))
        forces.append(sim.step(dt).force)
    forces = np.array(forces)
    assert np.all(forces[:, 0] < 0), forces
    assert np.all(np.abs(forces[:, 1:]) < 0.05 * np.abs(forces[:, :1])), forces


def test_sphere_classes_match_analytic_count():
    res, radius, centre = (40, 40, 40), 0.27, (0.5, 0.45, 0.52)
    sim = hf.Simulation(resolution=res, pressure_iterations=1)
    sim.set_probe(centre, radius)
    sim.step(0.01)
    classes = sim.cell_classes()
    expected = sphere_cell_counts(res, sim.cell_size, centre, radius)
    got = {k: int(np.count_nonzero(classes == k)) for k in expected}
    assert got == expected
    # And the solid count tracks the sphere's volume.
    solid_volume = (got[hf.CELL_INSIDE] + got[hf.CELL_BOUNDARY]) * sim.cell_size**3
    assert solid_volume == pytest.approx(4.0 / 3.0 * np.pi * radius**3, rel=0.03)


def test_smoke_rises_with_heat():
    sim = hf.Simulation(resolution=(24, 24, 24), heat_buoyancy=2.0, pressure_iterations=30, gravity=(0, 0, -9.81))
    sim.set_smoke_source((0.5, 0.5, 0.15), 0.1, density=1.0, temperature=1.0)
    for _ in range(15):
        sim.step(0.05)
    d = sim.density()
    z = (np.arange(24) + 0.5) / 24
    centroid_z = float((d.sum(axis=(0, 1)) * z).sum() / d.sum())
    assert d.max() > 0.5
    assert centroid_z > 0.25  # the source sits at 0.15 m; hot smoke has risen above it
    _, _, w = sim.velocity()
    assert w[10:14, 10:14, 4:12].mean() > 0.0


def test_maccormack_keeps_a_rising_puff_sharper():
    """A hot puff rising for 0.64 s: MacCormack's peak stays well above semi-Lagrangian's, and its
    clamped correction makes no new extrema (0 <= smoke <= the source's 1)."""
    peaks = {}
    for scheme in ("semi_lagrangian", "maccormack"):
        sim = hf.Simulation(resolution=(32, 32, 32), heat_buoyancy=8.0, advection=scheme, pressure_iterations=60)
        sim.set_smoke_source((0.5, 0.5, 0.2), 0.1, density=1.0, temperature=1.0)
        for _ in range(4):
            sim.step(0.04)
        sim.clear_smoke_source()
        for _ in range(16):
            sim.step(0.04)
        d = sim.density()
        assert d.min() >= 0.0 and d.max() <= 1.0 + 1e-6, scheme
        peaks[scheme] = float(d.max())
    assert peaks["maccormack"] > 1.2 * peaks["semi_lagrangian"], peaks


def _enstrophy(sim):
    """Integral of |curl u|^2 (1/s^2 m^3) from cell-centred velocities."""
    u, v, w = sim.velocity()
    uc, vc, wc = (u[1:] + u[:-1]) / 2, (v[:, 1:] + v[:, :-1]) / 2, (w[:, :, 1:] + w[:, :, :-1]) / 2
    h = sim.cell_size
    d = lambda f, axis: np.gradient(f, h, axis=axis)  # noqa: E731
    curl = (d(wc, 1) - d(vc, 2), d(uc, 2) - d(wc, 0), d(vc, 0) - d(uc, 1))
    return float(sum((c**2).sum() for c in curl) * h**3)


def test_vorticity_confinement_adds_swirl():
    """The same plume with stronger confinement ends with more enstrophy."""
    measured = []
    for epsilon in (0.0, 0.5, 2.0):
        sim = hf.Simulation(resolution=(32, 32, 32), heat_buoyancy=4.0, vorticity=epsilon, pressure_iterations=60)
        sim.set_smoke_source((0.5, 0.5, 0.2), 0.1, density=1.0, temperature=1.0)
        for _ in range(20):
            sim.step(0.04)
        measured.append(_enstrophy(sim))
    assert measured[0] < measured[1] < measured[2], measured
    assert measured[2] > 1.1 * measured[0], measured
