# SPDX-License-Identifier: GPL-3.0-or-later
"""Warnings raised in C++ reach Python's `logging` on a logger per engine layer (issue 19): the
engine's threads queue them (never taking the GIL) and the bindings deliver them on the host's
thread after the calls that may have queued something, or when hf.flush_log() is called."""

import logging
import time

import numpy as np

import hapticfluid as hf


def sweep_device():
    t = np.linspace(0.0, 2.0, 41)
    pos = np.stack([0.03 * np.sin(np.pi * t), np.zeros_like(t), 0.01 * np.sin(2 * np.pi * t)], axis=1)
    return hf.scripted_device(t, pos, loop=True, max_force=3.0)


def unconverged_sim():
    # Jacobi with tolerance 1e-4 and a cap of 4 sweeps cannot converge around a moving probe:
    # the simulation's once-only warning (test_pressure_promise.py) is raised in C++.
    return hf.Simulation(resolution=(16, 16, 16), gravity=(0, 0, 0), pressure_tolerance=1e-4,
                         pressure_iterations=4)


def fluid_warnings(caplog):
    return [r for r in caplog.records if r.name == "hapticfluid.fluid" and r.levelno == logging.WARNING]


def test_a_warning_from_the_simulation_thread_of_a_session_reaches_its_logger(caplog):
    """The warning is raised on the session's simulation thread (which owns the GL context and
    never holds the GIL); stop() delivers it on 'hapticfluid.fluid', once."""
    sim = unconverged_sim()
    caplog.set_level(logging.INFO, logger="hapticfluid")
    session = hf.HapticSession(sim, sweep_device(), workspace_scale=6.0, probe_radius=0.15,
                               force_gain=0.5, realtime=False)
    session.start()
    deadline = time.monotonic() + 30.0
    while sim.last_report is None or sim.last_report.converged:
        assert time.monotonic() < deadline, "the session's solve never missed its tolerance"
        time.sleep(0.05)
    session.stop()
    warnings = fluid_warnings(caplog)
    assert len(warnings) == 1, [w.getMessage() for w in warnings]
    assert warnings[0].getMessage().startswith("raise pressure_iterations")
    assert "relative residual" in warnings[0].getMessage()


def test_flush_log_delivers_at_once_and_only_once(caplog):
    sim = unconverged_sim()
    sim.set_probe((0.5, 0.5, 0.5), 0.2, velocity=(0.5, 0, 0))
    with caplog.at_level(logging.INFO, logger="hapticfluid"):
        assert not sim.step(0.01).converged   # the step's binding delivers the warning ...
        assert len(fluid_warnings(caplog)) == 1
        hf.flush_log()                          # ... so nothing is left to deliver
        sim.step(0.01)
        assert len(fluid_warnings(caplog)) == 1


def test_the_real_time_priority_warning_of_the_haptic_thread(caplog):
    """realtime=True asks for SCHED_FIFO on the haptic thread; when it is not granted the thread
    queues a warning (it used to write to stderr) that arrives on 'hapticfluid.haptics'."""
    sim = hf.Simulation(resolution=(16, 16, 16), gravity=(0, 0, 0), pressure_iterations=4)
    caplog.set_level(logging.INFO, logger="hapticfluid")
    with hf.HapticSession(sim, hf.null_device(), probe_radius=0.15, realtime=True) as session:
        deadline = time.monotonic() + 20.0
        while session.stats()["scheduling"] == "" and not session.stats()["realtime"]:
            assert time.monotonic() < deadline
            time.sleep(0.01)
        st = session.stats()
    haptics = [r for r in caplog.records if r.name == "hapticfluid.haptics"]
    if st["realtime"]:          # granted (a machine that allows SCHED_FIFO): nothing to say
        assert haptics == []
    else:
        assert [r.levelno for r in haptics] == [logging.WARNING]
        assert haptics[0].getMessage() == st["scheduling"]
        assert "not granted" in st["scheduling"]
