# SPDX-License-Identifier: GPL-3.0-or-later
"""Passive with a moving hand (issue 27, item 3): quick strokes of the simulated Falcon's hand
(3-5 cm in 0.25-0.4 s, random directions, a dead stop, then rest) in the live demo's geometry
(1 m domain, r = 0.08 m sphere, workspace fitted: scale 12.5) at 32^3, in air and in water, at
the default (amplified, derived) gain and with Physical 1:1 feel: the running energy the device delivers to the hand,
sum F(k-1).(x(k)-x(k-1)), stays <= 2 mJ at every instant and the hand settles within 1 mm (from 1 s
after the last stop: the hand carries the rendered added mass, 1 kg at the default gain in water,
and swings out the stop on its own 300 N/m). Gravity and the smoke source are off: a steady force (buoyancy, the plume's push)
does work on a hand that moves with it, which is the fluid's, not the rendering's.

The negative control runs the seed's rendering (the low-passed step force) without the passivity
controller at gain 1 in water: there the bounds fail, so they can tell. (At the derived gains the
seed alone stays passive in these strokes; what it cannot do is answer the hand between steps:
tests/cpp/test_haptic_coupling.cpp.)

48^3 is not in the suite (3-5 simulation steps a second: each case is as long, and the suite's
time goes to the cases above); the table of every case (32^3 and 48^3, air and water, the default
and the largest gain, the mechanism on and off) is the benchmark's, python3 -m
hapticfluid.bench.strokes (docs/BENCHMARKS.md, Quick strokes): with the grip's velocity fitted
within the encoder's resolution, 48^3 stayed within 1.34 mJ and settled within 0.47 mm; with the
fixed 4-period velocity the hand had settled up to 1.83 mm off in air and water had reached 2.12 mJ
once on a loaded machine."""

import pytest

from hapticfluid.bench.strokes import ENERGY_J, SETTLE_M, case_args, run_strokes as run_case


def run_strokes(fluid_density, **session_args):
    r = run_case(fluid_density, **session_args)
    return {"stats": r["stats"]}, r["energy_j"], r["drift_m"]


CASES = [("air", 1.2), ("water", 1000.0)]


@pytest.mark.parametrize("feel", ["amplified", "physical"])
@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_at_the_default_gain(name, density, feel):
    run, energy, drift = run_strokes(density, feel=feel)
    st = run["stats"]
    assert st["error"] is None and st["coupling"] is True
    assert energy <= ENERGY_J, (name, energy, st["force_gain"])
    assert drift <= SETTLE_M, (name, drift)


@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_with_the_simulation_slowed_to_5_hz(name, density):
    """Issue 27, item 4 (the slow half): the simulation waits out 0.2 s per step (5 Hz at most;
    3.7 Hz measured here); the derived gain is the same as at full speed (kGainStepCapS)."""
    run, energy, drift = run_strokes(density, min_sim_dt=0.2, max_sim_dt=0.25)
    st = run["stats"]
    assert st["error"] is None and st["coupling"] is True
    assert 0.0 < st["sim_rate_hz"] <= 5.5, st["sim_rate_hz"]
    assert energy <= ENERGY_J, (name, energy, st["force_gain"])
    assert drift <= SETTLE_M, (name, drift)


# The fast case is a fast case only when the machine lets the simulation run fast: a run whose
# simulation stepped under FAST_HZ (another process on the 2 cores: 24.5 Hz once in a full suite)
# measured something else, so it is run again, FAST_TRIES times at most; the bounds are the same.
FAST_HZ = 30.0
FAST_TRIES = 3


@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_with_the_simulation_at_60_hz(name, density):
    """Issue 27, item 4 (the fast half): steps of 1/60 s at 16^3, which this machine's llvmpipe
    runs at about 58 Hz (32^3 reaches 10-20 Hz); the derived gain is the same. The bounds are
    checked on a run that stepped at FAST_HZ or more."""
    rates = []
    for _ in range(FAST_TRIES):
        run, energy, drift = run_strokes(density, resolution=16, min_sim_dt=1.0 / 60.0)
        st = run["stats"]
        rates.append(st["sim_rate_hz"])
        if st["sim_rate_hz"] >= FAST_HZ:
            break
    assert st["error"] is None and st["coupling"] is True
    assert st["sim_rate_hz"] >= FAST_HZ, rates
    assert energy <= ENERGY_J, (name, energy, st["force_gain"])
    assert drift <= SETTLE_M, (name, drift)


SPEEDS = {"5 Hz": {"min_sim_dt": 0.2, "max_sim_dt": 0.25}, "60 Hz": {"resolution": 16, "min_sim_dt": 1.0 / 60.0}}


@pytest.mark.parametrize("speed", list(SPEEDS))
@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_at_the_largest_gain_slowed_and_fast(name, density, speed):
    """Issue 27, item 4 at the largest Force Gain the add-on accepts without the "unsafe"
    confirmation (Derive Gain off, Max Force 8 N: bench/strokes.py's 'largest'; 62.2 in air, 0.0746
    in water, the derived gains, now with twice the force). Measured in 2 runs of the four cases
    (one with a core kept busy; a third passed): at most 0.23-1.21 mJ into the hand in air and 0-1.44 mJ in water,
    settled within 0.04-0.09 mm; 3.3-5.1 steps a second slowed, 22-32 at "60 Hz" (16^3 reaches
    that only on an idle machine: the rate is not asserted here)."""
    run, energy, drift = run_strokes(density, **SPEEDS[speed], **case_args("largest", "on"))
    st = run["stats"]
    assert st["error"] is None and st["coupling"] is True
    assert energy <= ENERGY_J, (name, speed, energy, st["force_gain"], st["sim_rate_hz"])
    assert drift <= SETTLE_M, (name, speed, drift, st["force_gain"])


def test_without_controller_and_coupling_gain_1_strokes_fail():
    """The negative control: the seed's rendering (coupling off) without the controller at gain 1
    (the add-on's Force Gain with Derive Gain off) in water: the same strokes feed the hand. At
    the derived gains (above) the seed alone stays passive in these strokes (measured 1-15 uJ),
    so the bounds are checked where the rendering fails them."""
    run, energy, drift = run_strokes(1000.0, force_gain=1.0, allow_unsafe_gain=True, passivity=False, coupling=False)
    assert energy > ENERGY_J or drift > SETTLE_M, (energy, drift)
