# SPDX-License-Identifier: GPL-3.0-or-later
"""The multigrid solve's predictor (issue 20): the previous pressure scaled by the alpha that
minimises the starting residual, alpha = <b, A p> / <A p, A p>. Known answers: a warm start that
is the solution times k starts at the solution's own residual (alpha = 1 / k), where the plain
warm start would start at |1 - k| and fall back to p = 0; a warm start of noise never starts
above 1. A 22 x 18 x 16 closed box and an open one (sizes the other tests do not use)."""

import numpy as np
import pytest

import hapticfluid as hf

DT = 1.0 / 60.0


def _scene(open_top: bool) -> hf.Simulation:
    sim = hf.Simulation(resolution=(22, 18, 16), domain_size=(0.44, 0.36, 0.32), fluid_density=1.2,
                        heat_buoyancy=2.0, open_top=open_top, pressure_solver="multigrid",
                        pressure_tolerance=1e-6, pressure_iterations=60)
    sim.set_smoke_source((0.22, 0.18, 0.06), 0.05, density=1.0, temperature=3.0)
    sim.set_probe((0.15, 0.18, 0.18), 0.05, velocity=(0.3, 0.0, 0.1))
    for _ in range(3):
        sim.step(DT)
    return sim


@pytest.mark.parametrize("open_top", [False, True])
@pytest.mark.parametrize("k", [3.0, -2.0, 0.25])
def test_a_scaled_solution_is_unscaled(open_top, k):
    sim = _scene(open_top)
    before = sim.state()
    solved = sim.step(DT)
    assert solved.converged and solved.relative_residual <= 1e-6
    p = sim.state()["pressure"]
    start = dict(before)
    start["pressure"] = (k * p).astype(np.float32)
    sim.set_state(start)
    sim.pressure_tolerance = 1e-4
    r = sim.step(DT)
    # The plain warm start's residual is |1 - k| (0.75 to 3): it would have fallen back to p = 0.
    assert r.initial_relative_residual <= 2e-5, r
    assert r.pressure_iterations == 0 and r.converged
    assert r.relative_residual <= 1e-4
    np.testing.assert_allclose(sim.state()["pressure"], p, atol=2e-5 * float(np.abs(p).max()))


def test_noise_never_starts_worse_than_p_zero():
    sim = _scene(False)
    rng = np.random.default_rng(7)
    start = sim.state()
    scale = float(np.abs(start["pressure"]).max()) * 50.0
    start["pressure"] = rng.normal(0.0, scale, start["pressure"].shape).astype(np.float32)
    sim.set_state(start)
    sim.pressure_tolerance = 1e-4
    r = sim.step(DT)
    assert 0.0 < r.initial_relative_residual <= 1.0 + 1e-6
    assert r.converged and r.relative_residual <= 1e-4
