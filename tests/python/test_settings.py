# SPDX-License-Identifier: GPL-3.0-or-later
"""Settings as data: FluidSettings and HapticSessionSettings are the engine's structs with its
defaults and checks; a bad value names the setting; every engine error arrives as its own class."""

import copy
import time

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes


def test_fluid_settings_are_the_engines_defaults_and_a_simulation_keeps_them():
    s = hf.FluidSettings()
    assert s.resolution == (64, 64, 64) and s.pressure_solver == hf.PressureSolver.jacobi
    assert s.advection == hf.Advection.semi_lagrangian and s.cut_cells and s.conserve_smoke
    given = hf.FluidSettings(resolution=(16, 16, 16), pressure_solver="multigrid", pressure_tolerance=1e-3,
                             vorticity=0.25, fluid_density=1000.0)
    with hf.Simulation(given) as sim:
        used = sim.settings
    for name in hf.FluidSettings.fields():
        if name not in ("device", "backend", "cpu_threads"):  # requests ('', 0) against what is in use
            assert getattr(used, name) == getattr(given, name), name
    assert used.backend == sim.device["backend"] and used.backend in ("gpu", "cpu")
    assert used.cpu_threads == sim.device["threads"]
    # Keywords set the settings of the same names on a copy: the object given is not changed.
    with hf.Simulation(given, vorticity=0.5) as sim:
        assert sim.vorticity == pytest.approx(0.5)
    assert given.vorticity == pytest.approx(0.25)


_NICENESS_CHECK = r"""
import json, os, threading
import hapticfluid as hf

def threads():
    out = {}
    for tid in os.listdir("/proc/self/task"):
        try:
            stat = open(f"/proc/self/task/{tid}/stat").read()
            name = open(f"/proc/self/task/{tid}/comm").read().strip()
        except OSError:
            continue
        out[int(tid)] = (name, int(stat[stat.rindex(")") + 2:].split()[16]))
    return out

result = {"start": threads()[threading.get_native_id()][1]}  # the caller's niceness, as this process was started
hf.probe_device(backend="gpu")  # the driver's threads start here, at the caller's niceness
with hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16), backend="gpu", thread_niceness=7)) as sim:
    sim.step(0.01)
    result["software"] = bool(sim.device["software"])
    result["kept"] = sim.settings.thread_niceness
    result["nice"] = threads()
    result["caller"] = threads()[threading.get_native_id()][1]
with hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16), backend="gpu", thread_niceness=0)) as sim:
    sim.step(0.01)
    result["after"] = threads()
    result["warning"] = sim.device["warning"]
print(json.dumps(result))
"""


_CPU_NICENESS_CHECK = _NICENESS_CHECK.split("result = {")[0] + r"""
result = {"start": threads()[threading.get_native_id()][1]}
with hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16), backend="cpu", cpu_threads=3, thread_niceness=7)) as sim:
    sim.step(0.01)
    result["nice"] = threads()
    result["caller"] = threads()[threading.get_native_id()][1]
with hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16), backend="cpu", cpu_threads=3, thread_niceness=0)) as sim:
    sim.step(0.01)
    result["after"] = threads()
print(json.dumps(result))
"""


def test_thread_niceness_on_the_cpu_backend_reaches_its_device_thread_and_pool():
    """On the CPU backend the simulation's device thread ("hf-cpu") and its pool's threads (started
    by it, so named and niced alike) run the asked-for niceness above the caller's; the caller keeps
    its own. Each CPU simulation has its own pool, so one at 0 afterwards runs at the caller's."""
    import json
    import os
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _CPU_NICENESS_CHECK], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    r = json.loads(out.stdout.strip().splitlines()[-1])
    caller = r["start"]
    mine = [n for name, n in r["nice"].values() if name.startswith("hf-cpu")]
    assert len(mine) == 3 and all(n == min(19, caller + 7) for n in mine), (caller, r["nice"])  # device thread + 2 workers
    assert r["caller"] == caller, r
    after = [n for name, n in r["after"].values() if name.startswith("hf-cpu")]
    assert len(after) == 3 and all(n == caller for n in after), (caller, r["after"])


def test_thread_niceness_lowers_the_simulations_threads_and_the_drivers_only():
    """A live session beside Blender's drawing on llvmpipe asks for nicer simulation threads
    (hapticfluid.assembly.live_share). The GL worker ("hf-gl") and the driver's threads it
    computes on (llvmpipe's, made when the process's first context was: probe_device's here, at the
    caller's niceness) get it; the caller's thread keeps its own. Then a simulation at 0 takes the
    driver's threads back where the process may lower niceness (root; CAP_SYS_NICE), else its device
    warning says why not. In a fresh process: the driver's threads are the process's, shared by every
    simulation in it. Niceness is relative: the engine adds to the caller's (capped at 19), so the
    expected values are the caller's plus 7, and the test holds under `nice -n N` too."""
    import json
    import os
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _NICENESS_CHECK], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ))
    assert out.returncode == 0, out.stderr
    r = json.loads(out.stdout.strip().splitlines()[-1])
    caller = r["start"]
    nicer = min(19, caller + 7)
    assert r["kept"] == 7
    named = [(name, n) for name, n in r["nice"].values() if name.startswith(("hf-gl", "llvmpipe"))]
    assert named and all(n == nicer for _, n in named), (caller, r["nice"])
    if r["software"]:
        assert any(name.startswith("llvmpipe") for name, _ in named), r["nice"]
    assert r["caller"] == caller, r
    lp = [n for name, n in r["after"].values() if name.startswith("llvmpipe")]
    if r["software"]:
        if os.geteuid() == 0 or nicer == caller:  # taken back (or never moved: the caller was at 19)
            assert lp and all(n == caller for n in lp), (caller, r["after"])
        else:
            assert f"keep niceness {nicer}" in r["warning"], r["warning"]
    with pytest.raises(hf.InvalidArgumentError, match="thread_niceness must be 0 to 19.*got 20"):
        hf.FluidSettings(thread_niceness=20)
    with pytest.raises(TypeError, match="thread_niceness"):
        hf.FluidSettings(thread_niceness="low")


def test_viewport_first_on_the_cpu_is_nicer_and_caps_the_step_rate(small_sim):
    """Viewport First where the simulation computes on the CPU: niceness 10 and at most 30 steps a
    second (min_sim_dt 1/30 s); on a GPU or with Equal, niceness 0 and the engine's own rate. A
    session with that min_sim_dt steps no faster (an upper bound: load only slows it)."""
    from hapticfluid import assembly
    share = assembly.live_share(True, True)
    assert share == assembly.LiveShare(10, pytest.approx(1.0 / 30.0))
    assert assembly.live_share(False, True) == assembly.LiveShare(0, None)
    assert assembly.live_share(True, False) == assembly.LiveShare(0, None)
    settings = hf.HapticSessionSettings(min_sim_dt=share.min_sim_dt, realtime=False)
    t0 = time.monotonic()
    with hf.HapticSession(small_sim, hf.null_device(), settings) as session:  # started here
        time.sleep(0.6)
        steps = session.stats()["sim_steps"]
        elapsed = time.monotonic() - t0
    assert steps >= 1, "the session never stepped"
    assert steps <= elapsed * assembly.VIEWPORT_FIRST_STEP_RATE_HZ + 1, (steps, elapsed)


@pytest.mark.parametrize("cls, name, value, error, words", [
    (hf.FluidSettings, "pressure_solver", "cg", hf.InvalidArgumentError, ["pressure_solver", "'jacobi'", "'multigrid'"]),
    (hf.FluidSettings, "advection", 3, hf.InvalidArgumentError, ["advection", "'semi_lagrangian'", "'maccormack'"]),
    (hf.FluidSettings, "vorticity", "lots", TypeError, ["FluidSettings.vorticity must be a number", "str"]),
    (hf.FluidSettings, "vorticity", True, TypeError, ["FluidSettings.vorticity must be a number", "bool"]),
    (hf.FluidSettings, "open_top", 1, TypeError, ["FluidSettings.open_top must be True or False", "int 1"]),
    (hf.FluidSettings, "resolution", (16, 16), TypeError, ["FluidSettings.resolution"]),
    (hf.FluidSettings, "fluid_density", -1.0, hf.InvalidArgumentError, ["density"]),
    (hf.FluidSettings, "pressure_iterations", 0, hf.InvalidArgumentError, ["iterations"]),
    (hf.HapticSessionSettings, "filter", "median", hf.InvalidArgumentError, ["filter", "'lowpass'", "'none'"]),
    (hf.HapticSessionSettings, "slew_rate", -5.0, hf.InvalidArgumentError, ["slew_rate"]),
    (hf.HapticSessionSettings, "rate", "fast", TypeError, ["HapticSessionSettings.rate"]),
    (hf.HapticSessionSettings, "workspace_scale", (1.0, 2.0), hf.InvalidArgumentError, ["workspace_scale"]),
    (hf.HapticSessionSettings, "passivity_max_damping", 0.0, hf.InvalidArgumentError, ["passivity_max_damping"]),
    (hf.HapticSessionSettings, "probe_radius", -0.1, hf.InvalidArgumentError, ["probe_radius"]),
])
def test_a_bad_value_names_the_setting_and_changes_nothing(cls, name, value, error, words):
    s = cls()
    before = s.to_dict()
    with pytest.raises(error) as info:
        setattr(s, name, value)
    for w in words:
        assert w in str(info.value), (w, str(info.value))
    assert s.to_dict() == before
    with pytest.raises(error):  # the same through a keyword
        cls(**{name: value})


FLUID_GRID = ("resolution", "domain_size", "origin", "backend", "cpu_threads", "device", "thread_niceness")


def test_limits_are_what_the_engine_checks():
    """FluidSettings.limits(), which the add-on's fields and the bake's scene check read, is the
    engine's own check: each bound is taken, the next float32 (or integer) past it refused."""
    limits = hf.FluidSettings.limits()
    assert set(limits) == {"fluid_density", "vorticity", "smoke_weight", "heat_buoyancy", "smoke_dissipation",
                           "heat_dissipation", "pressure_iterations", "pressure_tolerance"}
    assert limits["vorticity"] == {"min": 0.0, "max": 1000.0, "max_exclusive": False}

    def past(x, direction):
        return float(np.nextafter(np.float32(x), np.float32(direction)))

    for name, r in limits.items():
        s = hf.FluidSettings()
        integer = isinstance(getattr(s, name), int)
        lo, hi = (int(r["min"]), int(r["max"])) if integer else (r["min"], r["max"])
        setattr(s, name, lo)
        with pytest.raises(hf.InvalidArgumentError):
            setattr(s, name, lo - 1 if integer else past(lo, -np.inf))
        if r["max_exclusive"]:
            with pytest.raises(hf.InvalidArgumentError):
                setattr(s, name, hi)
            setattr(s, name, past(hi, -np.inf))
        else:
            setattr(s, name, hi)
            with pytest.raises(hf.InvalidArgumentError):
                setattr(s, name, hi + 1 if integer else past(hi, np.inf))


def test_the_simulations_fluid_settings_are_fluid_settings_fields():
    """One table binds the fluid's settings: Simulation has a property for each FluidSettings field
    but the grid's, with the same docstring, and it refuses what FluidSettings refuses."""
    fluid = [n for n in hf.FluidSettings.fields() if n not in FLUID_GRID]
    assert len(fluid) == 15
    for name in fluid:
        prop = getattr(hf.Simulation, name)
        assert isinstance(prop, property) and getattr(hf.FluidSettings, name).__doc__ in prop.__doc__, name
    assert not any(isinstance(getattr(hf.Simulation, n, None), property) and getattr(hf.Simulation, n).fset
                   for n in FLUID_GRID)
    with hf.Simulation(hf.FluidSettings(resolution=(8, 8, 8))) as sim:
        with pytest.raises(TypeError, match="^Simulation.vorticity must be a number, got str 'x'$"):
            sim.vorticity = "x"
        with pytest.raises(hf.InvalidArgumentError, match="vorticity confinement must be between 0 and 1000"):
            sim.vorticity = 1001.0
        sim.vorticity = 1000.0
        assert sim.vorticity == 1000.0 and sim.settings.vorticity == 1000.0


def test_an_unknown_keyword_is_named_with_the_settings_that_exist(small_sim):
    with pytest.raises(TypeError, match="'pressure_sovler'.*pressure_solver"):
        hf.FluidSettings(pressure_sovler="multigrid")
    with pytest.raises(TypeError, match="Simulation.*'viscosity'"):
        hf.Simulation(resolution=(16, 16, 16), viscosity=1.0)
    with pytest.raises(TypeError, match="HapticSession.*'gain'.*force_gain"):
        hf.HapticSession(small_sim, hf.null_device(), gain=2.0)
    with pytest.raises(TypeError, match="settings must be a hapticfluid.HapticSessionSettings"):
        hf.HapticSession(small_sim, hf.null_device(), hf.FluidSettings())


def test_keywords_that_bound_each_other_may_come_in_any_order():
    # min_sim_dt <= max_sim_dt: each order of the two keywords is the same settings.
    a = hf.HapticSessionSettings(min_sim_dt=0.6, max_sim_dt=1.0)
    b = hf.HapticSessionSettings(max_sim_dt=1.0, min_sim_dt=0.6)
    assert a == b and a.min_sim_dt == pytest.approx(0.6)
    with pytest.raises(hf.InvalidArgumentError, match="min_sim_dt"):  # ... but the result is still checked
        hf.HapticSessionSettings(min_sim_dt=0.6)


def test_copies_are_independent_and_compare_by_value():
    a = hf.HapticSessionSettings(probe_radius=0.08, filter=hf.ForceFilter.none)
    for b in (a.copy(), copy.copy(a), copy.deepcopy(a)):
        assert b == a and b is not a
        b.probe_radius = 0.09
        assert b != a and a.probe_radius == pytest.approx(0.08)
    assert "probe_radius=0.08" in repr(a) and "ForceFilter.none" in repr(a)


def test_a_session_made_from_settings_runs_with_them(small_sim):
    settings = hf.HapticSessionSettings(probe_radius=0.15, ramp_time=0.2, max_force=3.0, trace=True,
                                        trace_seconds=2.0, realtime=False)
    with hf.HapticSession(small_sim, hf.null_device(), settings, slew_rate=150.0) as session:
        used = session.settings
    assert used.max_force == pytest.approx(3.0) and used.slew_rate == pytest.approx(150.0)
    assert used.trace and used.trace_seconds == pytest.approx(2.0) and used.probe_radius == pytest.approx(0.15)
    assert settings.slew_rate == pytest.approx(200.0)  # the keyword changed a copy only


def test_each_engine_error_reaches_python_as_its_own_class(small_sim):
    assert issubclass(hf.MeshNotClosedError, hf.InvalidArgumentError)
    assert issubclass(hf.InvalidArgumentError, ValueError) and issubclass(hf.HapticFluidError, RuntimeError)
    for cls in (hf.DeviceNotFoundError, hf.DeviceAccessDeniedError, hf.DeviceUnpluggedError):
        assert issubclass(cls, hf.DeviceError) and issubclass(cls, hf.HapticFluidError)
    assert issubclass(hf.GlError, hf.HapticFluidError) and issubclass(hf.VdbError, hf.HapticFluidError)
    # An open mesh: a box with one triangle taken away.
    vertices, triangles = meshes.box((0.2, 0.2, 0.2))
    at_centre = np.eye(4)
    at_centre[:3, 3] = 0.5
    with pytest.raises(hf.MeshNotClosedError, match="not closed"):
        small_sim.set_mesh_probe(vertices, triangles[1:], transform=at_centre)
    small_sim.set_mesh_probe(vertices, triangles, transform=at_centre)  # closed: taken
    small_sim.clear_probe()
    # A VDB file that cannot be written (its folder is a file).
    with pytest.raises(hf.VdbError):
        hf.write_vdb(__file__ + "/frame.vdb", np.zeros((8, 8, 8), np.float32), voxel_size=0.1)
    # No Falcon is plugged into the machines the tests run on.
    if not hf.list_falcons(probe_firmware=False):
        with pytest.raises(hf.DeviceNotFoundError, match="plugged in"):
            hf.open_falcon()


def test_an_unplugged_device_ends_the_session_with_its_own_error(small_sim):
    falcon = hf.open_simulated_falcon(unplug_after=300)  # about 0.3 s of 1 kHz packets
    try:
        session = hf.HapticSession(small_sim, falcon, probe_radius=0.15, workspace_scale=6.0, ramp_time=0.1,
                                   realtime=False)
        session.start()
        deadline = 30.0
        t0 = time.monotonic()
        while session.state != "failed" and time.monotonic() - t0 < deadline:
            time.sleep(0.02)
        assert session.state == "failed"
        with pytest.raises(hf.DeviceUnpluggedError, match="unplugged"):
            session.stop()
    finally:
        falcon.close()


def test_the_engine_fits_the_workspace_and_reports_where_it_put_it(small_sim):
    falcon = hf.open_simulated_falcon()
    try:
        info = falcon.info()
        edges = np.asarray(info.workspace_max) - np.asarray(info.workspace_min)
        session = hf.HapticSession(small_sim, falcon, fit_workspace=True, probe_radius=0.1, realtime=False)
        scale = np.asarray(session.workspace_scale)
        assert scale == pytest.approx(np.full(3, 1.0 / edges.max()), rel=1e-6)  # the 1 m domain, its tightest axis
        lo, hi = (np.asarray(c) for c in session.workspace_box)
        assert np.all(lo >= -1e-6) and np.all(hi <= 1.0 + 1e-6)  # inside the domain ...
        assert (hi - lo).max() == pytest.approx(1.0, rel=1e-5)  # ... filling it along that axis
        assert (lo + hi) / 2 == pytest.approx(np.full(3, 0.5), abs=1e-5)  # centred
        # Not fitted: the scale given, the box mapped with it.
        session = hf.HapticSession(small_sim, falcon, workspace_scale=2.0, probe_radius=0.1, realtime=False)
        lo, hi = (np.asarray(c) for c in session.workspace_box)
        assert hi - lo == pytest.approx(2.0 * edges, rel=1e-5)
    finally:
        falcon.close()


def test_one_grid_rule_for_the_bake_and_the_live_session():
    from hapticfluid import assembly

    g = assembly.grid((1.0, 0.5, 0.03), 32)
    assert g.cells == (32, 16, 8) and g.cell_size == pytest.approx(1.0 / 32)  # at least 8 per axis
    assert g.size == pytest.approx((1.0, 0.5, 0.25))
    s = assembly.fluid_settings((0.0, 0.0, 0.0), (1.0, 0.5, 0.5), 16, {"fluid_density": 1000.0, "gravity": [0, 0, -1]})
    assert s.resolution == (16, 8, 8) and s.fluid_density == pytest.approx(1000.0) and s.gravity[2] == -1.0
    assert not s.compute_residual


def test_the_engine_says_where_it_puts_the_probe_for_a_device_position(small_sim):
    falcon = hf.open_simulated_falcon()
    try:
        session = hf.HapticSession(small_sim, falcon, fit_workspace=True, probe_radius=0.1, realtime=False)
        scale = np.asarray(session.workspace_scale)
        offset = np.asarray(session.workspace_offset)
        inside = np.array([0.01, -0.02, 0.005])
        assert session.probe_origin(inside) == pytest.approx(offset + scale * inside, abs=1e-6)  # the map
        # Past a wall the probe is held one cell of fluid from it: 1 m - 1/16 m - 0.1 m.
        held = session.probe_origin(np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]))
        assert held[0, 0] == pytest.approx(1.0 - 1.0 / 16 - 0.1, abs=1e-4)  # (a hair more than a cell)
        assert held[1, 0] == pytest.approx(1.0 / 16 + 0.1, abs=1e-4)
        with pytest.raises(hf.InvalidArgumentError, match="probe_origin"):
            session.probe_origin(np.zeros((2, 2)))
    finally:
        falcon.close()


def test_a_gain_above_the_passive_one_needs_allow_unsafe_gain():
    with hf.Simulation(resolution=(16, 16, 16), fluid_density=1000.0) as water:
        falcon = hf.open_simulated_falcon()
        try:
            derived = hf.HapticSession(water, falcon, probe_radius=0.1, workspace_scale=6.0, realtime=False)
            passive = derived.stats()["force_gain"]
            assert 0.0 < passive < 1.0  # water at this scale: less than 1:1 renders passively
            with pytest.raises(hf.InvalidArgumentError, match="allow_unsafe_gain") as info:
                hf.HapticSession(water, falcon, probe_radius=0.1, workspace_scale=6.0, force_gain=1.0, realtime=False)
            assert f"{passive:.3g}" in str(info.value)  # names the largest passive gain
            at_limit = hf.HapticSession(water, falcon, probe_radius=0.1, workspace_scale=6.0, force_gain=passive,
                                        realtime=False)
            assert "unsafe" not in at_limit.stats()["force_gain_reason"]
            unsafe = hf.HapticSession(water, falcon, probe_radius=0.1, workspace_scale=6.0, force_gain=1.0,
                                      allow_unsafe_gain=True, realtime=False)
            assert "unsafe" in unsafe.stats()["force_gain_reason"]
        finally:
            falcon.close()
