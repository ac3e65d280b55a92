# SPDX-License-Identifier: GPL-3.0-or-later
"""Haptic devices and HapticSession from Python. Timing is never asserted tightly (a loaded
2-core machine runs these): structure and generous bounds only."""

import inspect
import math
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import hapticfluid as hf
from test_stub import public, stub_names


def wait_until(predicate, timeout=20.0, interval=0.01):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(interval)
    return predicate()


@pytest.fixture()
def sim():
    with hf.Simulation(resolution=(16, 16, 16), pressure_iterations=20, fluid_density=1000.0,
                       gravity=(0.0, 0.0, 0.0)) as s:
        yield s


def sweep_device(loop=True):
    t = np.linspace(0.0, 2.0, 41)
    pos = np.stack([0.03 * np.sin(np.pi * t), np.zeros_like(t), 0.01 * np.sin(2 * np.pi * t)], axis=1)
    return hf.scripted_device(t, pos, loop=loop, max_force=3.0)


# ---------------------------------------------------------------------------- devices


def test_scripted_device_interpolates_and_loops():
    d = hf.scripted_device([0.0, 1.0, 3.0], [(0, 0, 0), (0.02, 0, 0), (0.02, 0.04, 0)], loop=True)
    assert isinstance(d, hf.Device) and isinstance(d, hf.ScriptedDevice)
    s = d.state_at(0.5)
    np.testing.assert_allclose(s.position, [0.01, 0.0, 0.0], atol=1e-7)
    np.testing.assert_allclose(s.velocity, [0.02, 0.0, 0.0], atol=1e-7)
    np.testing.assert_allclose(d.state_at(3.0 + 2.5).position, [0.02, 0.03, 0.0], atol=1e-7)
    assert d.duration == 3.0 and d.loops and s.homed
    info = d.info()
    assert info.kind == "scripted" and info.max_force == 10.0
    np.testing.assert_allclose(info.workspace_max, [0.02, 0.04, 0.0])


def test_scripted_device_from_csv(tmp_path):
    path = tmp_path / "path.csv"
    path.write_text("t,x,y,z\n0,0,0,0\n2,0.04,0,-0.02\n")
    d = hf.scripted_device_from_csv(str(path))
    np.testing.assert_allclose(d.state_at(1.0).position, [0.02, 0.0, -0.01], atol=1e-7)
    np.testing.assert_allclose(d.state_at(5.0).position, [0.04, 0.0, -0.02], atol=1e-7)  # holds
    path.write_text("0,0,0,0\n1,x,0,0\n")
    with pytest.raises(hf.InvalidArgumentError, match=":2:"):
        hf.scripted_device_from_csv(str(path))


@pytest.mark.parametrize("times, positions", [
    ([], []),
    ([0.0, 1.0], [(0, 0, 0)]),
    ([1.0, 0.5], [(0, 0, 0), (0, 0, 0)]),
    ([0.0, math.nan], [(0, 0, 0), (0, 0, 0)]),
])
def test_scripted_device_rejects_bad_waypoints(times, positions):
    with pytest.raises(hf.InvalidArgumentError):
        hf.scripted_device(times, positions)


def test_host_device_velocity_from_pushes():
    d = hf.host_device(max_force=4.0)
    assert not d.read().homed  # nothing pushed yet: no force
    d.push_pose((0.0, 0.0, 0.0), time=1.0)
    d.push_pose((0.0, 0.01, 0.0), time=1.05)
    s = d.state_after(0.0)
    assert s.homed and d.pushes == 2
    np.testing.assert_allclose(s.velocity, [0.0, 0.2, 0.0], rtol=1e-5)
    np.testing.assert_allclose(d.state_after(0.025).position, [0.0, 0.015, 0.0], rtol=1e-5)
    np.testing.assert_allclose(d.state_after(1.0).position, [0.0, 0.02, 0.0], rtol=1e-5)  # capped
    with pytest.raises(hf.InvalidArgumentError, match="increase"):
        d.push_pose((0.0, 0.0, 0.0), time=1.0)
    d.push_pose((0.0, 0.0, 0.0))  # default time: now on time.monotonic(), later than 1.05
    assert d.read().homed


def test_host_device_rejects_pushes_too_close_for_a_finite_velocity():
    d = hf.host_device()
    d.push_pose((0.0, 0.0, 0.0), 0.0)
    with pytest.raises(hf.InvalidArgumentError, match="too close"):
        d.push_pose((0.01, 0.0, 0.0), 1e-300)  # dt > 0, but 0.01 m / 1e-300 s is no velocity
    state = d.read()
    assert np.all(np.isfinite(state.position)) and np.all(np.isfinite(state.velocity))
    d.push_pose((0.01, 0.0, 0.0), 0.01)  # the rejected push changed nothing
    np.testing.assert_allclose(d.state_after(0.0).velocity, (1.0, 0.0, 0.0), rtol=1e-6)


def test_null_device_and_close():
    with hf.null_device() as d:
        s = d.read()
        assert s.homed and list(s.position) == [0.0, 0.0, 0.0]
        d.write_force((1.0, 2.0, 3.0))
    with pytest.raises(hf.HapticFluidError, match="close"):
        d.read()
    with pytest.raises(hf.InvalidArgumentError):
        hf.null_device(max_force=0.0)


# ---------------------------------------------------------------------------- session


def test_session_runs_and_reports_sane_statistics(sim):
    device = sweep_device()
    session = hf.HapticSession(sim, device, workspace_scale=6.0, probe_radius=0.15, ramp_time=0.2,
                               force_gain=0.5, trace=True)
    assert session.state == "idle"
    session.start()
    assert session.state == "running"
    assert wait_until(lambda: session.stats()["sim_steps"] >= 5 and session.stats()["ticks"] >= 200)
    # The loop's pace against its own clock over the same half second (not a wall-clock rate): every
    # deadline of its period is run or counted as skipped, and it never runs ahead of its clock.
    nominal_hz = hf.HapticSessionSettings().rate
    before, t0 = session.stats(), time.monotonic()
    time.sleep(0.5)
    st, t1 = session.stats(), time.monotonic()
    deadlines = (t1 - t0) * nominal_hz
    counted = (st["ticks"] + st["skipped_periods"]) - (before["ticks"] + before["skipped_periods"])
    assert 0.9 * deadlines <= counted <= deadlines + 2, (counted, deadlines, st["skipped_periods"])
    assert st["error"] is None and st["state"] == "running"
    assert 0.0 < st["haptic_rate_hz"] <= 1.05 * nominal_hz  # 1 / mean period
    assert 0.0 <= st["jitter_p50_ms"] <= st["jitter_p99_ms"] <= st["jitter_max_ms"]
    assert 0.0 < st["period_p50_ms"] <= st["period_max_ms"]
    assert st["sim_rate_hz"] > 0.0 and st["sim_step_ms"] > 0.0 and 0.0 < st["sim_dt"] <= 0.05
    assert st["latency_samples"] > 0 and 0.0 < st["latency_p50_ms"] <= st["latency_max_ms"]
    assert st["realtime"] or "not granted" in st["scheduling"]
    latest = session.latest()
    assert set(latest) >= {"sim_force", "filtered_force", "commanded_force", "cutoff_hz", "position"}
    assert latest["cutoff_hz"] > 0.0
    session.stop()
    assert session.state == "stopped"
    assert np.all(session.latest_force == 0.0)
    np.testing.assert_array_equal(device.last_force, [0.0, 0.0, 0.0])  # stop commands zero
    trace = session.trace()
    n = len(trace["time"])
    assert n > 100
    for key in ("position", "sim_force", "filtered_force", "commanded_force"):
        assert trace[key].shape == (n, 3) and np.all(np.isfinite(trace[key]))
    assert np.all(np.diff(trace["time"]) > 0.0)
    assert np.linalg.norm(trace["commanded_force"], axis=1).max() <= 3.0 + 1e-6  # device maximum
    # The probe followed the device: its centre is the mapped device position.
    assert session.device is not None
    session.stop()  # a second stop is harmless


@pytest.mark.parametrize("scale", [(1.0, 1.0, 1.0), (1.0, 1.0, -1.0)])
def test_the_hand_force_in_world_axes_undoes_a_mirrored_axis(scale):
    """latest()['commanded_force_world'] is the commanded force in world axes as the engine's
    workspace map gives it (what the add-on draws): a mirrored axis (negative scale) pushes the
    device the other way, and the world force flips it back, so a buoyant probe's force points up
    (+z, against gravity) whatever the device's z."""
    with hf.Simulation(resolution=(16, 16, 16), pressure_iterations=10, fluid_density=1000.0) as sim:
        session = hf.HapticSession(sim, hf.null_device(max_force=5.0), probe_radius=0.15, force_gain=0.02,
                                   max_force=4.0, ramp_time=0.0, filter="none", realtime=False, passivity=False,
                                   workspace_scale=scale, fit_workspace=False)
        with session:
            assert wait_until(lambda: session.stats()["sim_steps"] >= 3
                              and np.linalg.norm(session.latest()["commanded_force"]) > 0.0)
            latest = session.latest()
    device = np.asarray(latest["commanded_force"])
    world = np.asarray(latest["commanded_force_world"])
    np.testing.assert_array_equal(world, np.sign(scale) * device)  # the same newtons, the mirror undone
    buoyancy = 0.02 * 1000.0 * 9.81 * 4.0 / 3.0 * np.pi * 0.15 ** 3  # gain x Archimedes, N (voxels: about)
    assert world[2] > 0.5 * buoyancy, (world, buoyancy)  # up in the world
    assert np.sign(device[2]) == np.sign(scale[2]), device  # down on the device when its z is mirrored
    assert abs(world[2]) > 3.0 * max(abs(world[0]), abs(world[1])), world


def test_session_context_manager_pause_resume(sim):
    device = hf.host_device(max_force=2.0)
    device.push_pose((0.0, 0.0, 0.0))
    with hf.HapticSession(sim, device, probe_radius=0.15, ramp_time=0.0, realtime=False,
                          prediction=True, filter="none") as session:
        assert session.state == "running"
        assert wait_until(lambda: session.stats()["force_frames"] >= 2)
        session.pause()
        assert session.state == "paused"
        assert wait_until(lambda: np.all(session.latest_force == 0.0), timeout=5.0)
        steps = session.stats()["sim_steps"]
        time.sleep(0.2)
        assert session.stats()["sim_steps"] <= steps + 1  # at most the step that was running
        session.resume()
        assert session.state == "running"
        assert wait_until(lambda: session.stats()["sim_steps"] > steps + 1)
        assert "not requested" in session.stats()["scheduling"]
    assert session.state == "stopped"


def test_device_error_propagates_as_haptic_fluid_error(sim):
    device = hf.host_device()
    device.push_pose((0.0, 0.0, 0.0))
    session = hf.HapticSession(sim, device, probe_radius=0.15)
    session.start()
    assert wait_until(lambda: session.stats()["ticks"] > 10)
    device.close()  # the device goes away under the running session
    assert wait_until(lambda: session.state == "failed", timeout=10.0)
    assert "close" in session.error
    assert session.stats()["error"] == session.error
    with pytest.raises(hf.HapticFluidError, match="close"):
        session.stop()
    session.stop()  # raised once
    with pytest.raises(hf.HapticFluidError):
        session.resume()


def test_context_manager_raises_the_device_error(sim):
    device = hf.host_device()
    device.push_pose((0.0, 0.0, 0.0))
    with pytest.raises(hf.HapticFluidError, match="close"):
        with hf.HapticSession(sim, device, probe_radius=0.15) as session:
            assert wait_until(lambda: session.stats()["ticks"] > 10)
            device.close()
            assert wait_until(lambda: session.state == "failed", timeout=10.0)


def test_a_driven_device_refuses_host_commands_and_a_second_session(sim):
    device = hf.null_device(max_force=2.0)
    first = hf.HapticSession(sim, device, probe_radius=0.15, realtime=False)
    second = hf.HapticSession(sim, device, probe_radius=0.15, realtime=False)
    with first:
        assert wait_until(lambda: first.stats()["ticks"] > 10)
        # Past the session's safety stage: refused, not interleaved with the session's commands.
        with pytest.raises(hf.HapticFluidError, match="in use.*write_force"):
            device.write_force((5.0, 0.0, 0.0))
        with pytest.raises(hf.HapticFluidError, match="in use.*read"):
            device.read()
        with pytest.raises(hf.HapticFluidError, match="in use"):
            second.start()
        assert second.state == "idle"
    assert device.read().homed  # free again
    device.write_force((1.0, 0.0, 0.0))


def test_session_stop_from_several_threads_at_once(sim):
    session = hf.HapticSession(sim, hf.null_device(), probe_radius=0.15, realtime=False)
    session.start()
    assert wait_until(lambda: session.stats()["ticks"] > 10)
    errors = []

    def stop():
        try:
            session.stop()
        except Exception as exc:  # pragma: no cover - the failure this test looks for
            errors.append(exc)

    threads = [threading.Thread(target=stop) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60.0)
    assert not any(t.is_alive() for t in threads)
    assert errors == [] and session.state == "stopped"


def test_stop_that_times_out_still_reports_the_force_output_stopped():
    # 48^3 with a fixed step: the simulation thread is nearly always mid-step, so stop(0) times
    # out waiting for it; force output has ended all the same and the state must say so.
    with hf.Simulation(resolution=(48, 48, 48), pressure_iterations=60) as big:
        timed_out = False
        for _ in range(5):
            session = hf.HapticSession(big, hf.null_device(), probe_radius=0.15, sim_dt=0.01, realtime=False)
            session.start()
            assert wait_until(lambda: session.stats()["sim_steps"] >= 1, timeout=60.0)
            try:
                session.stop(timeout=0.0)
            except hf.HapticFluidError as exc:
                assert "still running" in str(exc)
                timed_out = True
                assert session.state == "stopped"
                np.testing.assert_array_equal(session.latest_force, [0.0, 0.0, 0.0])
            session.stop(timeout=60.0)
            assert session.state == "stopped"
            if timed_out:
                break
        assert timed_out, "stop(0) never caught the simulation mid-step"


@pytest.mark.parametrize("kwargs, match", [
    (dict(filter="median"), "filter"),
    (dict(workspace_scale=0.0), "workspace_scale"),
    (dict(workspace_scale=(1.0, 2.0)), "workspace_scale"),
    (dict(probe_radius=0.6), "probe"),
    (dict(max_force=-1.0), "max_force"),
    (dict(max_force=10.5), "above the maximum"),
    (dict(slew_rate=0.0), "slew_rate"),
    (dict(rate=20.0), "rate"),
    (dict(rate=math.nan, trace=True), "rate"),
    (dict(rate=-1000.0, trace=True), "rate"),
    (dict(trace=True, trace_seconds=math.inf), "trace_seconds"),
    (dict(bandwidth_ratio=0.0), "bandwidth_ratio"),
    (dict(sim_dt=-0.1), "sim_dt"),
    (dict(force_gain=math.nan), "force_gain"),
])
def test_bad_session_arguments_say_what_to_change(sim, kwargs, match):
    with pytest.raises(hf.InvalidArgumentError, match=match):
        hf.HapticSession(sim, hf.null_device(), **kwargs)


def test_running_session_is_stopped_at_interpreter_exit():
    # This handler is registered before hapticfluid's, so it runs after it (atexit is LIFO).
    code = (
        "import atexit\n"
        "atexit.register(lambda: print('state after the exit hooks:', s.state, flush=True))\n"
        "import time, hapticfluid as hf\n"
        "sim = hf.Simulation(resolution=(16, 16, 16), pressure_iterations=5)\n"
        "s = hf.HapticSession(sim, hf.null_device(), probe_radius=0.15)\n"
        "s.start()\n"
        "time.sleep(0.3)\n"
        "assert s.state == 'running'\n"
        "print('exiting with a running session', flush=True)\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "exiting with a running session" in proc.stdout
    assert "state after the exit hooks: stopped" in proc.stdout
    assert "terminate" not in proc.stderr and "Traceback" not in proc.stderr


def test_stub_names_the_haptics_members():
    _, members = stub_names()
    for cls in ("Device", "DeviceInfo", "DeviceState", "ScriptedDevice", "HostDevice", "HapticSession"):
        real = {name for name, _ in inspect.getmembers(getattr(hf, cls))}
        stubbed = set(members[cls])
        for base in getattr(hf, cls).__mro__[1:]:  # a stubbed subclass inherits its base's stub
            stubbed |= set(members.get(base.__name__, ()))
        assert public(stubbed) == public(real), cls


def test_simulated_falcon_drives_a_session_and_its_unplug_is_reported(sim):
    falcon = hf.open_simulated_falcon(unplug_after=1500)  # about 1.5 s of 1 kHz packets
    session = hf.HapticSession(sim, falcon, workspace_scale=6.0, probe_radius=0.15, ramp_time=0.1)
    session.start()
    assert wait_until(lambda: session.state == "failed", timeout=30.0)
    st = session.stats()
    assert st["ticks"] > 100 and st["sim_steps"] > 0
    with pytest.raises(hf.HapticFluidError):
        session.stop()
    np.testing.assert_array_equal(session.latest_force, [0.0, 0.0, 0.0])
    falcon.close()


def test_session_moves_the_simulations_mesh_probe(sim):
    from hapticfluid import meshes

    vertices, triangles = meshes.box((0.2, 0.1, 0.1))
    turn = np.array([[0.0, -1.0, 0.0, 0.5], [1.0, 0.0, 0.0, 0.5], [0.0, 0.0, 1.0, 0.5], [0, 0, 0, 1.0]])
    sim.set_mesh_probe(vertices, triangles, transform=turn)
    device = hf.host_device()
    device.push_pose((0.02, 0.0, 0.0))
    # probe_radius=None keeps the simulation's probe: here the turned box.
    with hf.HapticSession(sim, device, workspace_scale=5.0, ramp_time=0.0) as session:
        assert wait_until(lambda: session.stats()["sim_steps"] >= 3)
        probe = sim.probe
    assert probe["kind"] == "mesh"
    transform = np.asarray(probe["transform"])
    np.testing.assert_allclose(transform[:3, :3], turn[:3, :3], atol=1e-7)  # orientation kept
    np.testing.assert_allclose(transform[:3, 3], [0.6, 0.5, 0.5], atol=1e-6)  # 0.5 + 5 x 0.02 m
