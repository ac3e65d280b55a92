# SPDX-License-Identifier: GPL-3.0-or-later
"""Devices and sessions at the edges: a looped script whose time lands on its last waypoint,
non-finite times, waypoints too close for a velocity, and one session per Simulation."""

import math
import time

import numpy as np
import pytest

import hapticfluid as hf

ISSUE_TIMES = [63.19510386607734, 66.75379394278342, 70.31248401948949]


def wait_until(pred, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if pred():
            return True
        time.sleep(0.01)
    return pred()


def test_looped_script_on_its_last_waypoint_is_the_end_of_the_last_segment():
    points = [(0.0, 0.0, 0.0), (0.01, 0.0, 0.0), (0.01, 0.02, 0.0)]
    d = hf.scripted_device(ISSUE_TIMES, points, loop=True)
    t = 14.234760306824295  # the issue's time: wraps exactly onto the last waypoint
    assert ISSUE_TIMES[0] + math.fmod(t, d.duration) == ISSUE_TIMES[-1]
    s = d.state_at(t)
    np.testing.assert_allclose(s.velocity, (0.0, 0.02 / (ISSUE_TIMES[2] - ISSUE_TIMES[1]), 0.0), rtol=1e-5)
    np.testing.assert_allclose(s.position, points[2], atol=1e-7)


@pytest.mark.parametrize("loop", [False, True])
@pytest.mark.parametrize("t", [math.inf, -math.inf, math.nan])
def test_scripted_state_at_a_non_finite_time_is_refused(loop, t):
    d = hf.scripted_device([0.0, 1.0], [(0.0, 0.0, 0.0), (0.01, 0.0, 0.0)], loop=loop)
    with pytest.raises(hf.InvalidArgumentError, match="finite time"):
        d.state_at(t)


def test_waypoints_too_close_for_a_finite_velocity_are_refused():
    with pytest.raises(hf.InvalidArgumentError, match="waypoints 0 and 1.*too close"):
        hf.scripted_device([0.0, 1e-300], [(0.0, 0.0, 0.0), (0.01, 0.0, 0.0)])
    still = hf.scripted_device([0.0, 1e-300, 1.0], [(0.0, 0.0, 0.0)] * 3)  # no motion: velocity 0, not NaN
    assert list(still.state_at(0.0).velocity) == [0.0, 0.0, 0.0]


def test_host_state_after_nan_is_refused():
    d = hf.host_device()
    d.push_pose((0.0, 0.0, 0.0), 1.0)
    with pytest.raises(hf.InvalidArgumentError, match="state_after.*NaN"):
        d.state_after(math.nan)
    assert np.all(np.isfinite(d.state_after(math.inf).position))


def test_a_second_session_on_the_same_simulation_waits_for_the_first_to_stop():
    with hf.Simulation(resolution=(16, 16, 16), pressure_iterations=10) as sim:
        first = hf.HapticSession(sim, hf.null_device(max_force=2.0), probe_radius=0.15, realtime=False)
        second = hf.HapticSession(sim, hf.null_device(max_force=2.0), probe_radius=0.15, realtime=False)
        first.start()
        try:
            with pytest.raises(hf.HapticFluidError, match="Simulation is in use.*stop that session first"):
                second.start()
            assert second.state == "idle"
        finally:
            first.stop()
        second.start()
        assert wait_until(lambda: second.stats()["sim_steps"] >= 2)
        second.stop()
        assert second.state == "stopped"


@pytest.mark.parametrize("make", [hf.host_device, hf.null_device,
                                  lambda max_force: hf.scripted_device([0.0], [(0.0, 0.0, 0.0)], max_force=max_force)])
def test_a_device_max_force_beyond_any_device_is_refused(make):
    with pytest.raises(hf.InvalidArgumentError, match="max_force.*at most 1000"):
        make(max_force=1e30)
    assert make(max_force=1000.0) is not None


def test_push_pose_beyond_a_million_metres_is_refused():
    d = hf.host_device()
    with pytest.raises(hf.InvalidArgumentError, match="push_pose position.*beyond"):
        d.push_pose((1e30, 0.0, 0.0), 1.0)
    assert d.pushes == 0
    d.push_pose((0.0, -1e6, 0.0), 1.0)
    assert d.pushes == 1


@pytest.mark.parametrize("kwargs, match", [(dict(stale_after=1e9), "stale_after.*at most 10"),
                                           (dict(fade_time=1e9), "fade_time.*at most 10"),
                                           (dict(max_force=8.0, slew_rate=3.0), "slew_rate.*down to zero on stop")])
def test_session_settings_that_would_turn_a_safety_off_are_refused(kwargs, match):
    with hf.Simulation(resolution=(8, 8, 8), pressure_iterations=1) as sim:
        with pytest.raises(hf.InvalidArgumentError, match=match):
            hf.HapticSession(sim, hf.null_device(), probe_radius=0.15, **kwargs)
