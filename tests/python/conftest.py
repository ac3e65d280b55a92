# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers of the pytest tier. Tests import the public package, never _core."""

import contextlib
import threading
import time

import numpy as np
import pytest

import hapticfluid as hf


def max_divergence(sim, sphere=None):
    """Largest |sum of outgoing face fluxes| over fluid cells (m/s): |div u| in units of 1/h.

    Without `sphere` (or with sim.cut_cells off) the faces carry the stored velocity and the
    fluid cells are those whose centre is outside the body (voxels). With `sphere` = (centre m,
    radius m, velocity m/s) of a translating sphere probe and cut cells on, each face's flux is
    w u + (1 - w) u_sphere with w its open fraction (sphere_open_fractions, a CPU reference of
    the ramp fractions) and the fluid cells are those with an open face (a pressure unknown)."""
    u, v, w = sim.velocity()
    if sphere is None or not sim.cut_cells:
        div = (u[1:] - u[:-1]) + (v[:, 1:] - v[:, :-1]) + (w[:, :, 1:] - w[:, :, :-1])
        fluid = sim.cell_classes() < hf.CELL_BOUNDARY
        return float(np.abs(div[fluid]).max())
    centre, radius, velocity = sphere
    fracs = [sphere_open_fractions(sim, centre, radius, axis) for axis in range(3)]
    fu, fv, fw = (f * comp + (1.0 - f) * velocity[a] for a, (f, comp) in enumerate(zip(fracs, (u, v, w))))
    div = (fu[1:] - fu[:-1]) + (fv[:, 1:] - fv[:, :-1]) + (fw[:, :, 1:] - fw[:, :, :-1])
    return float(np.abs(div[_linked_cells(fracs)]).max())


def _linked_cells(fracs):
    """Cells with an open interior face (a pressure unknown) from the three faces' fractions."""
    wu, wv, ww = (f > 0 for f in fracs)
    fluid = np.zeros(tuple(np.asarray(wu.shape) - (1, 0, 0)), dtype=bool)
    fluid[1:] |= wu[1:-1]
    fluid[:-1] |= wu[1:-1]
    fluid[:, 1:] |= wv[:, 1:-1]
    fluid[:, :-1] |= wv[:, 1:-1]
    fluid[:, :, 1:] |= ww[:, :, 1:-1]
    fluid[:, :, :-1] |= ww[:, :, 1:-1]
    return fluid


def cells_with_unknowns(sim, centre_m, radius_m):
    """Cells that hold a pressure unknown beside a sphere probe: with cut cells, those with an
    open face (sphere_open_fractions), including cut cells whose centre is in the sphere; with
    voxels, those whose centre is outside."""
    if not sim.cut_cells:
        return sim.cell_classes() < hf.CELL_BOUNDARY
    return _linked_cells([sphere_open_fractions(sim, centre_m, radius_m, axis) for axis in range(3)])


def sphere_open_fractions(sim, centre_m, radius_m, axis, samples=12, min_open=0.01):
    """CPU reference of the sphere probe's cut-cell fractions on the faces of `axis` (array of
    the velocity component's shape): the sphere smoothed into a radial ramp one cell wide whose
    volume is the sphere's (centre radius rc with rc^3 + rc / 4 = r^3, grid units), each face's
    covered part the ramp's mean over samples^2 midpoints, fractions under min_open taken to 0
    continuously (w < 2 min_open -> 2 (w - min_open))."""
    h = sim.cell_size
    n = np.asarray(sim.resolution)
    c = (np.asarray(centre_m, dtype=float) - np.asarray(sim.origin, dtype=float)) / h
    r3 = (radius_m / h) ** 3
    rc = radius_m / h
    for _ in range(20):
        rc -= (rc**3 + 0.25 * rc - r3) / (3 * rc * rc + 0.25)
    shape = n.copy()
    shape[axis] += 1
    open_ = np.ones(tuple(shape))
    b, cc = (axis + 1) % 3, (axis + 2) % 3
    outer = rc + 0.5
    lo = np.maximum(np.floor(c - outer).astype(int) - 1, 0)
    hi = np.minimum(np.ceil(c + outer).astype(int) + 2, shape)
    idx = np.stack(np.meshgrid(*[np.arange(lo[a], hi[a]) for a in range(3)], indexing="ij"), axis=-1)
    offs = (np.arange(samples) + 0.5) / samples
    pos = np.empty(idx.shape[:-1] + (samples, samples, 3))
    pos[..., axis] = idx[..., axis, None, None]
    pos[..., b] = idx[..., b, None, None] + offs[:, None]
    pos[..., cc] = idx[..., cc, None, None] + offs[None, :]
    dist = np.linalg.norm(pos - c, axis=-1)
    covered = np.clip(outer - dist, 0.0, 1.0).mean(axis=(-1, -2))
    frac = 1.0 - covered
    frac = np.where(frac >= 2 * min_open, np.minimum(frac, 1.0), np.maximum(2 * (frac - min_open), 0.0))
    open_[lo[0]:hi[0], lo[1]:hi[1], lo[2]:hi[2]] = frac
    return open_


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
