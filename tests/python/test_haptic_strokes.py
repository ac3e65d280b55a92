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
tests/cpp/test_haptic_coupling.cpp.)"""

import random

import numpy as np
import pytest

from hapticfluid.bench.feel import energy_into_hand, live_scene_run

START_S = 3.0      # hand clock (s after homing) of the first stroke: the force has ramped in
STROKES = 6
REST_S = 2.0       # after the last stop
ENERGY_J = 2e-3   # issue 27's bound (measured 0.007-0.68 mJ at the derived gains)
SETTLE_M = 1e-3


def stroke_path(seed=27):
    """Waypoints (t, x, y, z) of the strokes: each 3-5 cm in 0.25-0.4 s along a random direction
    (kept within 3.5 cm of the workspace centre), a dead stop, 0.4-0.8 s at rest."""
    rng = random.Random(seed)
    p = np.zeros(3)
    t = START_S
    path = [(t, 0.0, 0.0, 0.0)]
    for _ in range(STROKES):
        for _try in range(100):
            d = np.array([rng.gauss(0, 1) for _ in range(3)])
            d /= np.linalg.norm(d)
            q = p + rng.uniform(0.03, 0.05) * d
            if np.all(np.abs(q) <= 0.035):
                break
        t += rng.uniform(0.25, 0.4)
        path.append((t, *q))
        p = q
        t += rng.uniform(0.4, 0.8)
        path.append((t, *q))
    return path, t


def run_strokes(fluid_density, **session_args):
    path, end = stroke_path()
    run = live_scene_run(end + REST_S + 1.0, fluid_density=fluid_density, hand_path=path, gravity=(0.0, 0.0, 0.0),
                         source=False, **session_args)
    tr = run["trace"]
    # The trace starts when the session does; the hand's clock started at the end of homing, a
    # little before: align on the last stop, the last 50 ms in which the hand moved over 1 mm
    # (single encoder counts, 0.04 mm, are not motion).
    e = energy_into_hand(tr)
    t, x = tr["time"], tr["position"]
    lag = np.searchsorted(t, t - 0.05)
    moved = np.linalg.norm(x - x[lag], axis=1) > 1e-3
    stop = t[np.nonzero(moved)[0][-1]] if moved.any() else t[-1]
    after = tr["time"] >= stop + 1.0
    final = tr["position"][-1]
    drift = float(np.abs(tr["position"][after] - final).max()) if after.any() else float("inf")
    return run, float(e.max()), drift


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


@pytest.mark.parametrize("name,density", CASES)
def test_strokes_are_passive_with_the_simulation_at_60_hz(name, density):
    """Issue 27, item 4 (the fast half): steps of 1/60 s at 16^3, which this machine's llvmpipe
    runs at about 58 Hz (32^3 reaches 10-20 Hz); the derived gain is the same."""
    run, energy, drift = run_strokes(density, resolution=16, min_sim_dt=1.0 / 60.0)
    st = run["stats"]
    assert st["error"] is None and st["coupling"] is True
    assert st["sim_rate_hz"] >= 30.0, st["sim_rate_hz"]  # tolerant: a loaded machine slows it
    assert energy <= ENERGY_J, (name, energy, st["force_gain"])
    assert drift <= SETTLE_M, (name, drift)


def test_without_controller_and_coupling_gain_1_strokes_fail():
    """The negative control: the seed's rendering (coupling off) without the controller at gain 1
    (the add-on's Force Gain with Derive Gain off) in water: the same strokes feed the hand. At
    the derived gains (above) the seed alone stays passive in these strokes (measured 1-15 uJ),
    so the bounds are checked where the rendering fails them."""
    run, energy, drift = run_strokes(1000.0, force_gain=1.0, allow_unsafe_gain=True, passivity=False, coupling=False)
    assert energy > ENERGY_J or drift > SETTLE_M, (energy, drift)
