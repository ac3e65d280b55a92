"""Shared helpers of the pytest tier. Tests import the public package, never _core."""

import contextlib
import threading
import time

import numpy as np
import pytest

import hapticfluid as hf


def max_divergence(sim):
    """Largest |sum of outgoing face velocities| over fluid cells (m/s): |div u| in units of 1/h."""
    u, v, w = sim.velocity()
    div = (u[1:] - u[:-1]) + (v[:, 1:] - v[:, :-1]) + (w[:, :, 1:] - w[:, :, :-1])
    fluid = sim.cell_classes() < hf.CELL_BOUNDARY
    return float(np.abs(div[fluid]).max())


@contextlib.contextmanager
def step_in_background(sim, dt):
    """Runs sim.step(dt) on another thread and, once that step holds the GPU, yields an Event
    set when it finishes; joins the thread on exit. The step must be long (many pressure
    iterations) so the body of the with-block runs while it is still going."""
    started, done = threading.Event(), threading.Event()

    def work():
        started.set()
        sim.step(dt)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    try:
        started.wait()
        time.sleep(0.05)  # let the step take the GPU lock
        assert not done.is_set(), "the step finished too soon for this check"
        yield done
    finally:
        t.join()


@pytest.fixture(scope="session")
def small_sim():
    """One 16^3 simulation shared by the argument-checking tests (making a context costs time)."""
    return hf.Simulation(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0), pressure_iterations=5)
