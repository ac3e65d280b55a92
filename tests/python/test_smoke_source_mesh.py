# SPDX-License-Identifier: GPL-3.0-or-later
"""A closed mesh as the smoke source (Simulation.set_smoke_source_mesh): its coverage against a CPU
reference, the smoke a box source emits (known answers in 'hold' and 'rate' mode, still and
moving), the pose setter, and refused input that changes nothing."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes

RES = (12, 10, 11)
H = 0.05  # m, cubic cells
DOMAIN = tuple(n * H for n in RES)
DT = 0.02  # s
S = hf.SOURCE_SUBSAMPLES


def _still_sim():
    """No buoyancy, gravity or dissipation: emitted smoke stays where it was emitted."""
    return hf.Simulation(resolution=RES, domain_size=DOMAIN, gravity=(0.0, 0.0, 0.0), pressure_iterations=10)


def _translate(x, y, z):
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def _rotation(angle, axis):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    return m


def _winding(world_vertices, triangles, points):
    """Generalised winding number of a closed triangle mesh around each point (van Oosterom-Strackee)."""
    total = np.zeros(len(points))
    for tri in triangles:
        a, b, c = (world_vertices[i] - points for i in tri)
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        num = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la
               + np.einsum("ij,ij->i", c, a) * lb)
        total += 2.0 * np.arctan2(num, den)
    return total / (4.0 * np.pi)


def _reference_coverage(vertices, triangles, transform, heights=8):
    """The fraction of each cell inside the mesh, sampled on the engine's S x S vertical lines per
    cell at `heights` points each (so it errs by at most 1/(2 heights) per surface crossing)."""
    world = (np.c_[vertices, np.ones(len(vertices))] @ np.asarray(transform).T)[:, :3]
    sub = (np.arange(S) + 0.5) / S
    zs = (np.arange(heights) + 0.5) / heights
    i, j, k, a, b, z = np.meshgrid(*(np.arange(n) for n in RES), sub, sub, zs, indexing="ij")
    points = np.stack([i + a, j + b, k + z], axis=-1).reshape(-1, 3) * H
    inside = np.abs(_winding(world, triangles, points)) > 0.5
    return inside.reshape(*RES, -1).mean(axis=-1)


def test_coverage_of_a_turned_box_matches_a_cpu_reference():
    """After one 'hold' step from rest, density = density value x coverage in every cell."""
    v, t = meshes.box((0.22, 0.17, 0.2))
    transform = _translate(0.31, 0.26, 0.27) @ _rotation(0.7, (1.0, 2.0, 0.5))
    with _still_sim() as sim:
        sim.set_smoke_source_mesh(v, t, transform, density=2.0, temperature=4.0)
        sim.step(DT)
        got_d, got_t = sim.density(), sim.temperature()
    want = _reference_coverage(v, t, transform)
    assert np.count_nonzero((want > 0) & (want < 1)) > 30
    assert np.abs(got_d / 2.0 - want).max() <= 1 / 8 + 1e-4
    assert np.abs(got_t / 4.0 - want).max() <= 1 / 8 + 1e-4
    # the covered volume: the box's, within the z sampling of the reference
    assert got_d.sum() / 2.0 * H ** 3 == pytest.approx(0.22 * 0.17 * 0.2, rel=0.03)


def _box_source(sim, density, emission, centre=(0.3, 0.25, 0.275), size=(0.15, 0.2, 0.13)):
    v, t = meshes.box(size)
    sim.set_smoke_source_mesh(v, t, _translate(*centre), density=density, temperature=1.0, emission=emission)
    return float(np.prod(size))


def test_rate_source_emits_rate_times_volume_times_dt():
    rate = 3.0  # concentration per second
    steps = 5
    with _still_sim() as sim:
        # box faces between the sub-sample lines, so the sampled volume is the box's exactly
        volume = _box_source(sim, rate, "rate")
        totals = []
        for _ in range(steps):
            sim.step(DT)
            totals.append(sim.density().sum(dtype=np.float64) * H ** 3)  # concentration x m^3
    expected = [rate * volume * DT * (n + 1) for n in range(steps)]
    np.testing.assert_allclose(totals, expected, rtol=1e-4)


def test_hold_source_fills_its_volume_once():
    with _still_sim() as sim:
        volume = _box_source(sim, 0.7, "hold")
        for _ in range(3):
            sim.step(DT)
            assert sim.density().sum(dtype=np.float64) * H ** 3 == pytest.approx(0.7 * volume, rel=1e-4)
        assert sim.density().max() == pytest.approx(0.7)


def test_moving_rate_source_emits_the_same_and_leaves_a_trail():
    """Posed every step along x: the smoke per step stays rate x volume x dt (to one sub-column row)
    and the smoke lies where the box has been, not ahead of it."""
    rate = 2.0
    size = (0.15, 0.2, 0.13)
    volume = float(np.prod(size))
    row = size[1] * size[2] * H / S  # one row of sub-column lines through the box
    with _still_sim() as sim:
        _box_source(sim, rate, "rate", centre=(0.15, 0.25, 0.275), size=size)
        previous = 0.0
        for n in range(10):
            x = 0.15 + 0.0173 * n
            sim.set_smoke_source_pose(_translate(x, 0.25, 0.275))
            sim.step(DT)
            total = sim.density().sum(dtype=np.float64) * H ** 3
            assert abs((total - previous) - rate * volume * DT) <= rate * row * DT + 1e-7
            previous = total
        d = sim.density()
    per_x = d.sum(axis=(1, 2))
    last_hi = 0.15 + 0.0173 * 9 + size[0] / 2
    first_lo = 0.15 - size[0] / 2
    assert per_x[: int(first_lo / H)].sum() == 0.0
    assert per_x[int(np.ceil(last_hi / H)):].sum() == 0.0
    assert np.all(per_x[int(np.ceil(first_lo / H)):int(last_hi / H)] > 0.0)


def test_sphere_and_mesh_sources_replace_each_other():
    v, t = meshes.box((0.1, 0.1, 0.1))
    with _still_sim() as sim:
        assert sim.smoke_source is None
        sim.set_smoke_source_mesh(v, t, _translate(0.3, 0.25, 0.27), density=0.5, emission="rate")
        s = sim.smoke_source
        assert (s["kind"], s["vertex_count"], s["triangle_count"], s["emission"]) == ("mesh", 8, 12, "rate")
        assert s["density"] == 0.5
        np.testing.assert_allclose(s["transform"], _translate(0.3, 0.25, 0.27))
        sim.set_smoke_source((0.2, 0.2, 0.2), 0.06, density=0.4)
        s = sim.smoke_source
        assert (s["kind"], s["radius"], s["emission"]) == ("sphere", pytest.approx(0.06), "hold")
        sim.step(DT)
        assert sim.density().max() == pytest.approx(0.4)  # the sphere source still works
        sim.clear_smoke_source()
        assert sim.smoke_source is None


def test_refused_sources_change_nothing_and_say_what_to_do():
    v, t = meshes.box((0.1, 0.1, 0.1))
    with _still_sim() as sim:
        with pytest.raises(hf.InvalidArgumentError, match="set_smoke_source_mesh"):
            sim.set_smoke_source_pose(np.eye(4))
        sim.set_smoke_source_mesh(v, t, _translate(0.3, 0.25, 0.27))
        before = sim.smoke_source
        open_t = t[:-1]
        with pytest.raises(hf.InvalidArgumentError, match="smoke source mesh: .*closed"):
            sim.set_smoke_source_mesh(v, open_t)
        with pytest.raises(hf.InvalidArgumentError, match="move the smoke source into the domain"):
            sim.set_smoke_source_pose(_translate(5.0, 0.25, 0.27))
        with pytest.raises(hf.InvalidArgumentError, match="cut or scale down"):
            sim.set_smoke_source_mesh(v, t, np.diag([40.0, 40.0, 40.0, 1.0]))
        with pytest.raises(hf.InvalidArgumentError, match="emission"):
            sim.set_smoke_source_mesh(v, t, emission="pulse")
        with pytest.raises(hf.InvalidArgumentError, match="density"):
            sim.set_smoke_source_mesh(v, t, density=hf.MAX_SOURCE_DENSITY * 2)
        after = sim.smoke_source
        assert after["kind"] == "mesh"
        np.testing.assert_array_equal(after["transform"], before["transform"])
        # a source reaching out of the domain is accepted; its outside part emits nothing
        sim.set_smoke_source_pose(_translate(0.0, 0.25, 0.27))
        sim.step(DT)
        d = sim.density()
        assert d[0].sum() > 0 and d[2:].sum() == 0.0
