# SPDX-License-Identifier: GPL-3.0-or-later
"""The pressure solve keeps its promise (issue 18 item 2): a warm start never starts worse than a
cold one, tolerance mode reaches its tolerance or says it did not. Grids the other physics
tests do not use (28^3, 20^3)."""

import logging

import numpy as np
import pytest

import hapticfluid as hf

DT = 1.0 / 120.0  # s


def test_slow_impulsive_start_in_a_closed_box_reaches_tolerance_quickly():
    """Water at rest around a still sphere, then the sphere starts at 5 cm/s and stops again: every
    step of the closed box starts no worse than p = 0 and reaches 1e-5 in <= 10 multigrid
    iterations, reported as converged."""
    sim = hf.Simulation(resolution=(28, 28, 28), domain_size=(0.56, 0.56, 0.56), fluid_density=1000.0,
                        pressure_solver="multigrid", pressure_tolerance=1e-5, pressure_iterations=40)
    centre = [0.28, 0.28, 0.28]
    sim.set_probe(centre, 0.08)
    rows = []
    for step in range(12):
        speed = 0.05 if 3 <= step < 8 else 0.0  # impulsive start at step 3, impulsive stop at step 8
        if speed:
            centre[0] += speed * DT
        sim.set_probe(centre, 0.08, velocity=(speed, 0, 0))
        r = sim.step(DT)
        rows.append((step, speed, r.initial_relative_residual, r.pressure_iterations, r.relative_residual,
                     r.converged))
    table = "\n".join(f"{s:2d} v={v:.2f} start={i:.3g} its={n:2d} end={e:.2e} conv={c}" for s, v, i, n, e, c in rows)
    for _, _, start, its, end, conv in rows:
        assert start <= 1.0 + 1e-6, table  # never worse than a cold start
        assert its <= 10, table
        assert end <= 1.5e-5 and conv, table


def test_a_solve_that_stops_at_the_cap_says_so_once(caplog):
    """Jacobi, tolerance 1e-4 with a cap of 4 sweeps cannot converge from rest: every step reports
    converged False and the simulation logs one warning naming the fix, not one per step; in
    fixed-count mode nothing is promised and converged stays True."""
    sim = hf.Simulation(resolution=(20, 20, 20), gravity=(0, 0, 0), pressure_tolerance=1e-4,
                        pressure_iterations=4)
    sim.set_probe((0.5, 0.5, 0.5), 0.2, velocity=(0.5, 0, 0))
    with caplog.at_level(logging.WARNING, logger="hapticfluid"):
        reports = [sim.step(0.01) for _ in range(3)]
    assert [r.converged for r in reports] == [False, False, False]
    assert all(r.relative_residual > 1e-4 for r in reports)
    warnings = [rec for rec in caplog.records if rec.name == "hapticfluid.fluid" and rec.levelno == logging.WARNING]
    assert len(warnings) == 1, [w.getMessage() for w in warnings]
    assert warnings[0].getMessage().startswith("raise pressure_iterations")
    assert reports[0].warning == warnings[0].getMessage() and reports[1].warning == ""
    sim.pressure_tolerance = 0.0
    assert sim.step(0.01).converged


def test_a_tolerance_below_the_float32_floor_is_refused_naming_the_floor():
    """FLT_EPSILON * n / 16 (n: the most cells on an axis) is the lowest residual float32 pressure
    reached on 16^3-64^3; a tolerance under it is refused at construction and when set, and the
    message names the floor; the floor itself is accepted."""
    sim = hf.Simulation(resolution=(40, 20, 20), domain_size=(1.0, 0.5, 0.5))
    floor = sim.pressure_tolerance_floor
    assert floor == pytest.approx(np.finfo(np.float32).eps * 40 / 16, rel=1e-6)
    with pytest.raises(hf.InvalidArgumentError, match=r"below what float32 can reach .*floor 2\.98023\d*e-07\); use at least 3e-07"):
        sim.pressure_tolerance = 2.0e-7
    assert sim.pressure_tolerance == 0.0  # nothing changed
    sim.pressure_tolerance = 3.0e-7
    with pytest.raises(hf.InvalidArgumentError, match="pressure tolerance 2e-07 is below"):
        hf.Simulation(resolution=(40, 20, 20), domain_size=(1.0, 0.5, 0.5), pressure_tolerance=2.0e-7)
