# SPDX-License-Identifier: GPL-3.0-or-later
"""HapticSession field snapshots (drawn by the Blender add-on while a session runs) and the
defaults the engine exports for the add-on."""

import time

import numpy as np
import pytest

import hapticfluid as hf
from conftest import step_in_background


def wait_for(condition, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.005)
    return False


def test_snapshots_follow_the_steps_and_hold_the_last_fields():
    sim = hf.Simulation(resolution=(16, 16, 16), pressure_iterations=10)
    sim.set_smoke_source(centre=(0.5, 0.5, 0.2), radius=0.15, density=1.0, temperature=4.0)
    device = hf.host_device()
    device.push_pose((0.0, 0.0, 0.0))
    session = hf.HapticSession(sim, device, probe_radius=0.1, sim_dt=0.01, snapshot=0.0, snapshot_temperature=True,
                               realtime=False)
    assert session.snapshot() is None
    with session:
        assert wait_for(lambda: session.snapshot() is not None and session.snapshot()["sequence"] >= 2)
        first = session.snapshot()
        assert wait_for(lambda: session.snapshot()["sequence"] > first["sequence"])
    last = session.snapshot()
    assert last["steps"] == sim.steps == session.stats()["sim_steps"]
    assert last["sequence"] == session.stats()["snapshots"]
    assert last["time"] == pytest.approx(sim.time)
    assert last["resolution"] == (16, 16, 16)
    assert last["density"].shape == (16, 16, 16) and last["density"].dtype == np.float32
    assert not last["density"].flags.writeable
    np.testing.assert_array_equal(last["density"], sim.density())
    np.testing.assert_array_equal(last["temperature"], sim.temperature())
    assert last["density"][8, 8, 3] == pytest.approx(1.0, abs=1e-3)  # the emitter's centre cell
    assert last["temperature"][8, 8, 3] == pytest.approx(4.0, abs=1e-3)
    assert first["density"].shape == (16, 16, 16)  # an older snapshot stays valid


def test_snapshot_returns_while_a_long_step_holds_the_gpu():
    sim = hf.Simulation(resolution=(16, 16, 16), pressure_iterations=10)
    device = hf.host_device()
    device.push_pose((0.0, 0.0, 0.0))
    session = hf.HapticSession(sim, device, snapshot=0.0, realtime=False)
    with session:
        assert wait_for(lambda: session.snapshot() is not None)
        sim.pressure_iterations = 10000
        with step_in_background(sim, 0.01) as done:
            snap = session.snapshot()
            assert not done.is_set(), "snapshot() waited for the GPU step"
        assert snap is not None and snap["temperature"] is None
        session.stop(timeout=120.0)


def test_snapshots_off_by_default_and_bad_interval_refused(small_sim):
    small_sim.set_probe(centre=(0.5, 0.5, 0.5), radius=0.1)
    session = hf.HapticSession(small_sim, hf.null_device())
    assert session.snapshot() is None
    with pytest.raises(hf.InvalidArgumentError, match="snapshot"):
        hf.HapticSession(small_sim, hf.null_device(), snapshot=-0.5)


def test_default_workspace_offset_centres_the_device_workspace():
    sim = hf.Simulation(resolution=(16, 8, 8), domain_size=(2.0, 1.0, 1.0), origin=(1.0, 0.0, -1.0),
                        pressure_iterations=2)
    device = hf.open_simulated_falcon()
    try:
        info = device.info()
        session = hf.HapticSession(sim, device, workspace_scale=(4.0, 4.0, -2.0), probe_radius=0.2)
        mid = 0.5 * (info.workspace_min + info.workspace_max)
        domain_centre = np.array([2.0, 0.5, -0.5])
        np.testing.assert_allclose(session.workspace_offset + session.workspace_scale * mid, domain_centre,
                                   atol=1e-6)
        np.testing.assert_array_equal(session.workspace_scale, [4.0, 4.0, -2.0])
        given = hf.HapticSession(sim, device, workspace_offset=(0.1, 0.2, 0.3), probe_radius=0.2)
        np.testing.assert_allclose(given.workspace_offset, [0.1, 0.2, 0.3], atol=1e-7)
    finally:
        device.close()


def test_defaults_are_the_sessions_settings_defaults(small_sim):
    defaults = hf.haptic_session_defaults()
    assert defaults == hf.HapticSessionSettings().to_dict()
    assert defaults["force_gain"] is None  # None: the session derives it
    assert 0.0 < defaults["max_cutoff_per_rate"] <= 0.5
    # A session made without settings runs with exactly these (the engine's) defaults.
    session = hf.HapticSession(small_sim, hf.null_device(), probe_radius=0.1)
    used = session.settings.to_dict()
    assert used.pop("probe_radius") == pytest.approx(0.1) and defaults.pop("probe_radius") is None
    assert used == defaults
