# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python API: shapes, units, settings, errors and the GIL."""

import math
import threading
import time

import numpy as np
import pytest

import hapticfluid as hf
from conftest import cells_with_unknowns, step_in_background


def test_device_is_reported(small_sim):
    info = small_sim.device
    assert info["renderer"] and info["vendor"] and info["version"]
    assert isinstance(info["software"], bool)
    if info["backend"] == "gpu":
        major, minor = (int(x) for x in info["version"].split()[0].split(".")[:2])
        assert (major, minor) >= (4, 3) and info["threads"] == 0
    else:
        assert info["backend"] == "cpu" and info["threads"] >= 1 and not info["software"]
        assert f"{info['threads']} thread" in info["renderer"]
    assert "0:" in hf.list_egl_devices() or "surfaceless" in hf.list_egl_devices()


def test_geometry_and_arrays(small_sim):
    sim = small_sim
    assert sim.resolution == (16, 16, 16)
    assert sim.cell_size == pytest.approx(1.0 / 16)
    np.testing.assert_allclose(sim.domain_size, (1, 1, 1))
    sim.set_probe((0.5, 0.5, 0.5), 0.2, velocity=(0.1, 0, 0))
    report = sim.step(0.01)
    assert report.force.shape == (3,) and np.all(np.isfinite(report.force))
    assert report.pressure_iterations == 5
    assert 0.0 <= report.relative_residual < 1.5
    assert set(report.gpu_ms) >= {"voxelize", "classify", "advect", "divergence", "pressure", "project", "force"}
    assert all(v >= 0 for v in report.gpu_ms.values())
    assert report.wall_ms > 0
    d = sim.density()
    assert d.shape == (16, 16, 16) and d.dtype == np.float32
    u, v, w = sim.velocity()
    assert u.shape == (17, 16, 16) and v.shape == (16, 17, 16) and w.shape == (16, 16, 17)
    p = sim.pressure()
    assert p.shape == (16, 16, 16) and np.all(np.isfinite(p))
    c = sim.cell_classes()
    assert c.dtype == np.uint8 and set(np.unique(c)) == {0, 1, 2, 3}
    assert sim.probe["radius"] == pytest.approx(0.2)
    np.testing.assert_allclose(sim.last_report.force, report.force)


def test_hydrostatic_pressure_is_physical():
    sim = hf.Simulation(resolution=(16, 16, 16), fluid_density=1000.0, pressure_iterations=2)
    sim.step(0.01)
    p = sim.pressure()
    # 0 Pa at the top of the box, rho g depth below it, at cell centres.
    depth = 1.0 - (np.arange(16) + 0.5) / 16
    np.testing.assert_allclose(p[3, 7, :], 1000.0 * 9.81 * depth, rtol=1e-4, atol=1e-2)
    sim.fluid_density = 1.0  # a later setting does not rewrite the pressure of the last step
    np.testing.assert_allclose(sim.pressure()[3, 7, :], 1000.0 * 9.81 * depth, rtol=1e-4, atol=1e-2)
    np.testing.assert_allclose(sim.pressure(hydrostatic=False), 0.0, atol=1e-3)


def test_time_and_reset(small_sim):
    sim = hf.Simulation(resolution=(16, 16, 16), pressure_iterations=3)
    sim.set_smoke_source((0.5, 0.5, 0.3), 0.15)
    sim.step(0.02)
    sim.step(0.02)
    assert sim.steps == 2 and sim.time == pytest.approx(0.04)
    assert sim.density().max() > 0.5
    sim.reset()
    assert sim.steps == 0 and sim.time == 0.0 and sim.density().max() == 0.0


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"resolution": (4, 16, 16)}, "at least 8"),
        ({"resolution": (16, 16, 16), "domain_size": (1.0, 2.0, 1.0)}, "cubic"),
        ({"domain_size": (0.0, 0.0, 0.0), "resolution": (16, 16, 16)}, "positive"),
        ({"domain_size": (math.nan, 1.0, 1.0), "resolution": (16, 16, 16)}, "finite"),
        ({"fluid_density": -1.0, "resolution": (16, 16, 16)}, "density"),
        ({"pressure_iterations": 0, "resolution": (16, 16, 16)}, "iterations"),
        ({"advection": "upwind", "resolution": (16, 16, 16)}, "maccormack"),
        ({"vorticity": -0.5, "resolution": (16, 16, 16)}, "confinement"),
        ({"gravity": (0.0, 0.0, math.inf), "resolution": (16, 16, 16)}, "gravity"),
        ({"resolution": (2047, 2047, 2047)}, "too large"),
        ({"device": "banana", "resolution": (16, 16, 16)}, "banana"),
        ({"fluid_density": 1e38, "resolution": (16, 16, 16)}, "density"),
        ({"domain_size": (1e20, 1e20, 1e20), "resolution": (16, 16, 16)}, "cell size"),
        ({"origin": (1e30, 0.0, 0.0), "resolution": (16, 16, 16)}, "origin"),
        ({"open_top": True, "gravity": (1.0, 0.0, -9.81), "resolution": (16, 16, 16)}, "open top"),
    ],
)
def test_bad_construction_is_explained(kwargs, words):
    with pytest.raises(hf.InvalidArgumentError, match=words):
        hf.Simulation(**kwargs)


def test_bad_probe_and_step_are_explained(small_sim):
    sim = small_sim
    with pytest.raises(hf.InvalidArgumentError, match="finite"):
        sim.set_probe((math.nan, 0.5, 0.5), 0.1)
    with pytest.raises(hf.InvalidArgumentError, match="finite"):
        sim.set_probe((0.5, 0.5, 0.5), 0.1, velocity=(math.inf, 0, 0))
    with pytest.raises(hf.InvalidArgumentError, match="not inside the domain"):
        sim.set_probe((0.95, 0.5, 0.5), 0.1)
    with pytest.raises(hf.InvalidArgumentError, match="not inside the domain"):
        sim.set_probe((5.0, 0.5, 0.5), 0.1)
    with pytest.raises(hf.InvalidArgumentError, match="at least one cell"):
        sim.set_probe((0.5, 0.5, 0.5), 0.01)
    with pytest.raises(hf.InvalidArgumentError, match="at least one cell"):
        sim.set_probe((0.1, 0.5, 0.5), 0.1)  # touching the -x wall: no fluid face there
    with pytest.raises(hf.InvalidArgumentError, match="cannot fit"):
        sim.set_probe((0.5, 0.5, 0.5), 0.48)
    sim.set_probe((0.17, 0.5, 0.5), 0.1)  # a little over one cell of fluid between it and the wall
    with pytest.raises(hf.InvalidArgumentError, match="speed"):
        sim.set_probe((0.5, 0.5, 0.5), 0.1, velocity=(1e37, 0, 0))
    for dt in (0.0, -0.01, math.nan, math.inf, 1e-40, 1e300, 100.0):
        with pytest.raises(hf.InvalidArgumentError, match="time step"):
            sim.step(dt)
    with pytest.raises(hf.InvalidArgumentError, match="1e-40"):
        sim.step(1e-40)  # reported as given, not rounded to 0
    with pytest.raises(hf.InvalidArgumentError, match="open top"):
        sim.gravity = (0.0, 0.0, -9.81)
        sim.open_top = True
        sim.gravity = (0.0, 9.81, 0.0)
    sim.open_top = False
    sim.gravity = (0.0, 0.0, -9.81)
    for resolution in ((-8, 8, 8), (4, 16, 16), (1 << 20, 8, 8)):
        with pytest.raises(hf.InvalidArgumentError, match="resolution"):
            hf.estimate_bytes(resolution)
    with pytest.raises(hf.InvalidArgumentError, match="iterations"):
        sim.pressure_iterations = -3
    with pytest.raises(hf.InvalidArgumentError, match="outside the domain"):
        sim.set_smoke_source((9.0, 9.0, 9.0), 0.1)
    with pytest.raises(TypeError):
        sim.set_probe((0.5, 0.5), 0.1)
    # A rejected value changes nothing.
    assert sim.pressure_iterations == 5
    # The errors are ValueErrors too, and engine failures share one base class.
    assert issubclass(hf.InvalidArgumentError, ValueError)
    assert issubclass(hf.InvalidArgumentError, hf.HapticFluidError)
    assert issubclass(hf.HapticFluidError, RuntimeError)


def test_settings_round_trip(small_sim):
    sim = hf.Simulation(resolution=(16, 16, 16), advection="maccormack", vorticity=0.3, open_top=True)
    assert sim.advection == hf.Advection.maccormack and sim.open_top and sim.vorticity == pytest.approx(0.3)
    sim.advection = "semi_lagrangian"  # a member's name stands for it
    sim.heat_buoyancy = 1.5
    sim.smoke_weight = 0.2
    assert sim.advection == hf.Advection.semi_lagrangian
    assert sim.settings.advection == hf.Advection.semi_lagrangian and sim.settings.smoke_weight == pytest.approx(0.2)
    assert sim.heat_buoyancy == pytest.approx(1.5) and sim.smoke_weight == pytest.approx(0.2)
    sim.set_smoke_source((0.5, 0.5, 0.2), 0.12, density=1.0, temperature=2.0)
    sim.advection = "maccormack"
    for _ in range(3):
        assert np.all(np.isfinite(sim.step(0.02).force))
    assert np.isfinite(sim.density()).all()


def test_step_releases_the_gil():
    sim = hf.Simulation(resolution=(32, 32, 32), pressure_iterations=100)
    sim.set_probe((0.5, 0.5, 0.5), 0.15, velocity=(0.2, 0, 0))
    sim.step(0.01)  # compile everything first
    ticks = 0
    done = threading.Event()

    def work():
        for _ in range(3):
            sim.step(0.01)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    assert ticks > 5  # the main thread ran Python while the steps ran


def test_close_frees_and_later_calls_are_explained():
    with hf.Simulation(resolution=(8, 8, 8)) as sim:
        sim.step(0.01)
        assert not sim.closed
    assert sim.closed
    with pytest.raises(hf.HapticFluidError, match="closed"):
        sim.step(0.01)
    with pytest.raises(hf.HapticFluidError, match="closed"):
        sim.density()
    assert sim.device["renderer"]  # what it ran on stays known
    sim.close()  # closing twice is harmless


def test_closed_box_pressure_keeps_zero_mean():
    """In a closed box the pressure is defined up to a constant; the engine pins its mean at 0 so
    it does not drift over a long session."""
    sim = hf.Simulation(resolution=(16, 16, 16), heat_buoyancy=2.0, vorticity=0.3, pressure_iterations=20)
    sim.set_smoke_source((0.5, 0.5, 0.25), 0.15, temperature=2.0)
    for i in range(300):
        x = 0.5 + 0.2 * math.sin(i * 0.05)
        sim.set_probe((x, 0.5, 0.6), 0.15, velocity=(0.2 * 0.05 / 0.02 * math.cos(i * 0.05), 0, 0),
                      angular_velocity=(0, 0, 3.0))
        sim.step(0.02)
    p = sim.pressure(hydrostatic=False)
    fluid = cells_with_unknowns(sim, (x, 0.5, 0.6), 0.15)  # with cut cells, cut cells' centres may be inside
    spread = float(p[fluid].max() - p[fluid].min())
    assert spread > 0
    assert abs(float(p[fluid].mean())) < 1e-4 * spread + 1e-6


def test_state_taken_during_a_step_is_one_snapshot():
    """state() from another thread while a step runs holds the fields and the clock of the same
    step: it waits for that step rather than pairing the old step count with new fields."""
    sim = hf.Simulation(resolution=(48, 48, 48), pressure_iterations=1500, heat_buoyancy=1.0)
    sim.set_smoke_source((0.5, 0.5, 0.2), 0.1, density=1.0, temperature=5.0)
    sim.step(0.02)
    with step_in_background(sim, 0.02):
        state = sim.state()
    assert state["steps"] == sim.steps == 2
    assert state["time"] == pytest.approx(sim.time)
    np.testing.assert_array_equal(state["density"], sim.density())
    sim.close()


def test_getters_do_not_wait_for_a_running_step():
    """Host-side state is read under its own short lock: Blender's UI thread (or a haptic loop)
    can read and set it while a long GPU step runs."""
    sim = hf.Simulation(resolution=(48, 48, 48), pressure_iterations=1500)
    sim.set_probe((0.5, 0.5, 0.5), 0.15, velocity=(0.2, 0, 0))
    sim.step(0.01)
    with step_in_background(sim, 0.01) as done:
        observed = (sim.time, sim.steps, sim.pressure_iterations, sim.probe["radius"], sim.closed)
        sim.set_probe((0.55, 0.5, 0.5), 0.15)
        sim.vorticity = 0.1
        finished_during_reads = done.is_set()
    assert observed[1] == 1 and not finished_during_reads
