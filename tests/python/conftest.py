"""Shared helpers of the pytest tier. Tests import the public package, never _core."""

import numpy as np
import pytest

import hapticfluid as hf


def max_divergence(sim):
    """Largest |sum of outgoing face velocities| over fluid cells (m/s): |div u| in units of 1/h."""
    u, v, w = sim.velocity()
    div = (u[1:] - u[:-1]) + (v[:, 1:] - v[:, :-1]) + (w[:, :, 1:] - w[:, :, :-1])
    fluid = sim.cell_classes() < hf.CELL_BOUNDARY
    return float(np.abs(div[fluid]).max())


@pytest.fixture(scope="session")
def small_sim():
    """One 16^3 simulation shared by the argument-checking tests (making a context costs time)."""
    return hf.Simulation(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0), pressure_iterations=5)
