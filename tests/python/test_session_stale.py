# SPDX-License-Identifier: GPL-3.0-or-later
"""The stale-force threshold follows the simulation's measured rate: a slow simulation's force
reaches the hand between its frames (the stalled case fades: tests/cpp/test_haptic_loop.cpp)."""

import time

import numpy as np
import pytest

import hapticfluid as hf


def test_defaults_are_exported():
    d = hf.haptic_session_defaults()
    assert d["stale_periods"] == 3.0 and d["stale_after_max"] == 3.0 and d["stale_after"] == pytest.approx(0.1)


def slow_session_forces(**stale):
    """|commanded force| sampled for 2 s from a session whose simulation steps about 1.5 times a
    second (min_sim_dt 0.6 s of wall time per step): a buoyant sphere gives a steady force."""
    with hf.Simulation(resolution=(16, 16, 16), pressure_iterations=10, fluid_density=1000.0) as sim:
        session = hf.HapticSession(sim, hf.null_device(max_force=5.0), probe_radius=0.15, force_gain=0.02,
                                   max_force=4.0, ramp_time=0.0, filter="none", min_sim_dt=0.6, max_sim_dt=0.8,
                                   realtime=False, passivity=False, **stale)
        with session:
            end = time.monotonic() + 30.0
            while session.stats()["sim_steps"] < 4 and time.monotonic() < end:  # past the start's transient
                time.sleep(0.01)
            samples = []
            t_end = time.monotonic() + 2.0
            while time.monotonic() < t_end:
                samples.append(float(np.linalg.norm(session.latest()["commanded_force"])))
                time.sleep(0.005)
            stats = session.stats()
    return np.array(samples), stats


def test_a_slow_simulation_still_reaches_the_hand():
    forces, stats = slow_session_forces()
    rate = stats["sim_rate_hz"]
    # Its pace against its own steps (not a wall-clock rate): one step per min_sim_dt (0.6 s), or
    # per step where a loaded machine's step takes longer; never faster.
    assert 1.0 / rate >= 0.95 * 0.6 and 1.0 / rate <= 1.25 * max(0.6, 1e-3 * stats["sim_step_ms"]) + 0.05, \
        (rate, stats["sim_step_ms"])
    # 3 measured periods (about 2 s at 1.5 Hz) within [0.1, 3] s
    assert stats["stale_after"] == pytest.approx(min(max(3.0 / rate, 0.1), 3.0), rel=0.2)
    expected = 0.02 * 1000.0 * 9.81 * 4.0 / 3.0 * np.pi * 0.15 ** 3  # gain x Archimedes, N (voxels: about)
    assert forces.min() > 0.5 * expected, (forces.min(), expected)


def test_a_fixed_short_threshold_would_drop_it():
    # The old behaviour (0.1 s whatever the rate): the force fades to zero 0.3 s (0.1 s + 0.2 s
    # fade) after each frame, so for about half of every 0.6 s period.
    forces, stats = slow_session_forces(stale_periods=1.0, stale_after_max=0.1)
    assert stats["stale_after"] == pytest.approx(0.1)
    assert forces.max() > 1.0 and (forces == 0.0).mean() > 0.2, (forces == 0.0).mean()


@pytest.mark.parametrize("kwargs, name", [(dict(stale_periods=0.5), "stale_periods"),
                                          (dict(stale_periods=float("nan")), "stale_periods"),
                                          (dict(stale_after_max=0.0), "stale_after_max"),
                                          (dict(stale_after_max=11.0), "stale_after_max")])
def test_bad_stale_settings_name_the_argument(kwargs, name):
    with hf.Simulation(resolution=(16, 16, 16)) as sim:
        with pytest.raises(hf.InvalidArgumentError, match=name):
            hf.HapticSession(sim, hf.null_device(), **kwargs)
