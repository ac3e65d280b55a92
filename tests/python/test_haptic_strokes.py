# SPDX-License-Identifier: GPL-3.0-or-later
"""Passive with a moving hand (issue 27, item 3): quick strokes of the simulated Falcon's hand
(3-5 cm in 0.25-0.4 s, random directions, a dead stop, then rest) in the live demo's geometry
(1 m domain, r = 0.08 m sphere, workspace fitted: scale 12.5) at 32^3, in air and in water, at
the default (amplified, derived) gain and with Physical 1:1 feel: the running energy the device delivers to the hand,
sum F(k-1).(x(k)-x(k-1)), stays <= 2 mJ at every instant and the hand settles within 1 mm (from 1 s
after the last stop: the hand carries the rendered added mass, 1 kg at the default gain in water,
and swings out the stop on its own 300 N/m). Gravity and the smoke source are off: a steady force (buoyancy, the plume's push)
does work on a hand that moves with it, which is the fluid's, not the rendering's.

A rendering that sends nothing would pass those bounds, so every case also asserts a floor on what
the hand feels: a peak force, and energy the rendering takes from the moving hand (the drag and the
added mass the hand pushes against; FLOOR below, with the figures measured).

Two negative controls: at the shipped (derived) gain with the mechanism off (the seed's low-passed
step force, no virtual coupling, no passivity controller) in the fast case's settings, the same
strokes feed the hand far beyond the bounds, so it is the mechanism, not the gain, that passes
them; and the seed's rendering at gain 1 in water without the controller.

48^3 is not in the suite (3-5 simulation steps a second: each case is as long, and the suite's
time goes to the cases above); the table of every case (32^3 and 48^3, air and water, the default
and the largest gain, the mechanism on and off) is the benchmark's, python3 -m
hapticfluid.bench.strokes (docs/BENCHMARKS.md, Quick strokes): with the grip's velocity fitted
within the encoder's resolution, 48^3 stayed within 1.34 mJ and settled within 0.47 mm; with the
fixed 4-period velocity the hand had settled up to 1.83 mm off in air and water had reached 2.12 mJ
once on a loaded machine."""

import numpy as np
import pytest

from hapticfluid.bench.feel import energy_into_hand
from hapticfluid.bench.strokes import ENERGY_J, SETTLE_M, case_args, run_strokes as run_case

CASES = [("air", 1.2), ("water", 1000.0)]

# What the hand must at least feel in these strokes: its peak |force| (N), and the energy the
# rendering takes from the moving hand over the run (J; the running sum F(k-1).(x(k)-x(k-1)) ends
# at minus that or lower). Measured at the shipped gains (2026-12-04, 32^3 at 4-9 Hz under load,
# 16^3 at 20-44 Hz): 1.1-2.1 N and 38-274 mJ taken wherever the gain renders the fluid
# amplified (in air, and in water, where Physical feel has the same gain); Physical feel in air
# (gain 1 on a 1.3 g added mass) 0.06-0.56 N and 3.7-6.9 mJ. A zero force gives 0 N and 0 J.
FLOOR = {"amplified": (0.5, 10e-3), "physical in air": (0.02, 1e-3)}

# The fast case is a fast case only when the machine steps 16^3 that fast (58 Hz on an idle
# machine here; 20-32 Hz with a core busy). Each run's bounds and floors are asserted; the session
# must keep the pace its steps allow; a run whose steps took longer than 1 / FAST_HZ is tried once
# more, and if it is still slow the test skips, saying how long the steps took.
FAST_HZ = 30.0
FAST_TRIES = 2
FAST = {"resolution": 16, "min_sim_dt": 1.0 / 60.0}
SLOW = {"min_sim_dt": 0.2, "max_sim_dt": 0.25}


def run_strokes(fluid_density, **session_args):
    r = run_case(fluid_density, **session_args)
    st = r["stats"]
    assert st["error"] is None and st["coupling"] is True, st
    return r


def step_pace(trace):
    """(median time between two steps' pose reads, median time from a step's pose read to the first
    haptic period with its force: the step's own duration on this machine), s."""
    t, pose = trace["time"], trace["step_pose_time"]
    have = np.isfinite(pose)
    steps = np.unique(pose[have])
    first = np.searchsorted(pose[have], steps)  # pose times only grow: each step's first period
    return float(np.median(np.diff(steps))), float(np.median(t[have][first] - steps))


def assert_passive_and_felt(r, what, floor="amplified"):
    """Issue 27's bounds, and the floor of what the hand felt."""
    st, tr = r["stats"], r["trace"]
    peak_n = float(np.linalg.norm(tr["commanded_force"], axis=1).max())
    taken_j = -float(energy_into_hand(tr)[-1])
    interval, step = step_pace(tr)
    figures = (what, f"peak energy {1e3 * r['energy_j']:.3f} mJ", f"drift {1e3 * r['drift_m']:.3f} mm",
               f"peak {peak_n:.3f} N", f"taken {1e3 * taken_j:.1f} mJ", f"gain {st['force_gain']:.4g}",
               f"steps every {1e3 * interval:.0f} ms, each {1e3 * step:.0f} ms",
               f"haptic periods: longest {1e3 * float(np.diff(tr['time']).max()):.1f} ms, "
               f"{st['skipped_periods']} skipped")
    print("MEASURED", *figures)
    assert r["energy_j"] <= ENERGY_J, figures
    assert r["drift_m"] <= SETTLE_M, figures
    least_n, least_j = FLOOR[floor]
    assert peak_n >= least_n and taken_j >= least_j, figures


def kept_pace(r, min_sim_dt, what):
    """The session stepped as fast as the machine let it (a step waits for min_sim_dt only when it
    finished sooner); True when that was FAST_HZ or more."""
    interval, step = step_pace(r["trace"])
    assert interval <= 1.25 * max(min_sim_dt, step) + 0.002, \
        (what, f"the session waited between steps: one every {1e3 * interval:.1f} ms, each took {1e3 * step:.1f} ms "
               f"(min_sim_dt {1e3 * min_sim_dt:.1f} ms)")
    return 1.0 / interval >= FAST_HZ, f"16^3 steps took {1e3 * step:.0f} ms (median: {1.0 / interval:.1f} Hz)"


def fast_strokes(density, what, floor="amplified", **session_args):
    """The fast case: every run's bounds and floors asserted; a slow machine's run tried again, then
    skipped with its step time."""
    said = []
    for _ in range(FAST_TRIES):
        r = run_strokes(density, **FAST, **session_args)
        assert_passive_and_felt(r, what, floor)
        fast, pace = kept_pace(r, FAST["min_sim_dt"], what)
        if fast:
            return r
        said.append(pace)
    pytest.skip(f"slow machine: {'; '.join(said)}, under {FAST_HZ:g} Hz: ran as a slower case (its bounds and "
                f"floors held)")


@pytest.mark.parametrize("feel", ["amplified", "physical"])
@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_at_the_default_gain(name, density, feel):
    r = run_strokes(density, feel=feel)
    assert_passive_and_felt(r, (name, feel), "physical in air" if (feel, name) == ("physical", "air") else "amplified")


@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_with_the_simulation_slowed_to_5_hz(name, density):
    """Issue 27, item 4 (the slow half): the simulation waits out 0.2 s per step (5 Hz at most;
    3.7 Hz measured here); the derived gain is the same as at full speed (kGainStepCapS)."""
    r = run_strokes(density, **SLOW)
    st = r["stats"]
    assert 0.0 < st["sim_rate_hz"] <= 5.5, st["sim_rate_hz"]  # never faster than its 0.2 s floor
    assert_passive_and_felt(r, name)


@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_with_the_simulation_at_60_hz(name, density):
    """Issue 27, item 4 (the fast half): steps of 1/60 s at 16^3, which this machine's llvmpipe
    runs at about 58 Hz idle (32^3 reaches 10-20 Hz); the derived gain is the same."""
    fast_strokes(density, name)


SPEEDS = {"5 Hz": SLOW, "60 Hz": FAST}


@pytest.mark.parametrize("speed", list(SPEEDS))
@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_at_the_largest_gain_slowed_and_fast(name, density, speed):
    """Issue 27, item 4 at the largest Force Gain the add-on accepts without the "unsafe"
    confirmation (Derive Gain off, Max Force 8 N: bench/strokes.py's 'largest'; 62.2 in air, 0.0746
    in water, the derived gains, now with twice the force). Measured in 2 runs of the four cases
    (one with a core kept busy; a third passed): at most 0.23-1.21 mJ into the hand in air and 0-1.44 mJ in water,
    settled within 0.04-0.09 mm; 3.3-5.1 steps a second slowed, 22-32 at "60 Hz" (16^3 reaches
    that only on an idle machine: a slower machine's run skips after its bounds, as above)."""
    if speed == "60 Hz":
        fast_strokes(density, (name, speed), **case_args("largest", "on"))
    else:
        assert_passive_and_felt(run_strokes(density, **SPEEDS[speed], **case_args("largest", "on")), (name, speed))


def test_without_the_mechanism_the_shipped_gain_feeds_the_hand():
    """The negative control at the shipped gain (F2 of the 2026-12-04 test audit): the derived gain in
    water, with the virtual coupling and the passivity controller off (the seed's low-passed step
    force), in the fast case's settings, where the mechanism on passes (above). Measured: 2.2 J
    into the hand at 34 Hz (and 6.6-12.6 mJ at 32^3 under load, 7.2 J at 22 Hz: the benchmark), so it
    is the mechanism that passes the bounds, not a gain small enough to pass alone."""
    r = run_case(1000.0, **FAST, **case_args("default", "off"))
    st = r["stats"]
    assert st["error"] is None and st["coupling"] is False and st["force_gain"] == pytest.approx(0.0746, abs=1e-4), st
    assert r["energy_j"] > ENERGY_J, (r["energy_j"], r["drift_m"], st["sim_rate_hz"])


def test_without_controller_and_coupling_gain_1_strokes_fail():
    """The negative control: the seed's rendering (coupling off) without the controller at gain 1
    (the add-on's Force Gain with Derive Gain off) in water: the same strokes feed the hand."""
    r = run_case(1000.0, force_gain=1.0, allow_unsafe_gain=True, passivity=False, coupling=False)
    assert r["energy_j"] > ENERGY_J or r["drift_m"] > SETTLE_M, (r["energy_j"], r["drift_m"])
