# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: is the rendering passive with a hand that moves (issue 27, item 3)?

Quick strokes of the simulated Falcon's hand (3-5 cm in 0.25-0.4 s, random directions, a dead
stop, 0.4-0.8 s at rest, six of them, then 2 s of rest) in the live demo's geometry (1 m domain,
r = 0.08 m sphere, workspace fitted: scale 12.5; gravity and the smoke source off: a steady
force does work on a hand that moves with it, which is the fluid's, not the rendering's). For
every case (grid 32^3 and 48^3, air and water, at the default gain and at the largest Force Gain
the add-on lets a user pick without the "unsafe" confirmation, with Max Force at its largest,
8 N) it runs the strokes with the rendering as shipped (virtual coupling and passivity
controller on) and with both off (the seed's low-passed step force at the same gain), and
reports the largest running energy delivered to the hand, sum F(k-1).(x(k)-x(k-1)) (mJ), and
how far the hand drifts from 1 s after the last stop (mm). Bounds (issue 27): 2 mJ, 1 mm.

Each case is a real session of about 12 s. Run alone:
``python3 -m hapticfluid.bench.strokes [--quick] [--json PATH]``.
"""

from __future__ import annotations

import random
import sys
from typing import Dict, List, Optional

import numpy as np

from hapticfluid.bench import report
from hapticfluid.bench.feel import PASSIVE_LIMIT, energy_into_hand, live_scene_run

START_S = 3.0      # hand clock (s after homing) of the first stroke: the force has ramped in
STROKES = 6
REST_S = 2.0       # after the last stop
ENERGY_J = 2e-3    # issue 27's bounds
SETTLE_M = 1e-3
UI_MAX_FORCE_N = 8.0  # the add-on's largest Max Force (live_props.py)

FLUIDS = {"air": 1.2, "water": 1000.0}
# The gains: the default (Derive Gain on, Amplified) and the largest Force Gain Start accepts
# without Allow Unsafe Gain (Derive Gain off; live_props.py allows up to 1e6 behind that
# confirmation only), with Max Force at the add-on's largest.
GAINS = {"default": {}, "largest": {"force_gain": PASSIVE_LIMIT, "max_force": UI_MAX_FORCE_N}}
# The rendering as shipped, and the mechanism off: the seed's rendering at the same gain, no controller.
CONTROLLER = {"on": {}, "off": {"coupling": False, "passivity": False, "allow_unsafe_gain": True}}


def stroke_path(seed: int = 27):
    """Waypoints (t, x, y, z) of the strokes: each 3-5 cm in 0.25-0.4 s along a random direction
    (kept within 3.5 cm of the workspace centre), a dead stop, 0.4-0.8 s at rest; and the last stop's time."""
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


def run_strokes(fluid_density: float, resolution: int = 32, **session_args) -> Dict[str, object]:
    """One stroke run: the session's stats, the largest running energy into the hand (J), the
    hand's drift from 1 s after the last stop (m) and the run's trace (feel.live_scene_run's)."""
    path, end = stroke_path()
    run = live_scene_run(end + REST_S + 1.0, resolution=resolution, fluid_density=fluid_density, hand_path=path,
                         gravity=(0.0, 0.0, 0.0), source=False, **session_args)
    tr = run["trace"]
    # The trace starts when the session does; the hand's clock started at the end of homing, a
    # little before: align on the last stop, the last 50 ms in which the hand moved over 1 mm
    # (single encoder counts, 0.04 mm, are not motion).
    e = energy_into_hand(tr)
    t, x = tr["time"], tr["position"]
    lag = np.searchsorted(t, t - 0.05)
    moved = np.linalg.norm(x - x[lag], axis=1) > 1e-3
    stop = t[np.nonzero(moved)[0][-1]] if moved.any() else t[-1]
    # A hand still moving in the last second (it never settled) is measured over the last 0.5 s.
    after = t >= min(stop + 1.0, t[-1] - 0.5)
    drift = float(np.abs(x[after] - x[-1]).max())
    return {"stats": run["stats"], "energy_j": float(e.max()), "drift_m": drift, "trace": tr}


def case_args(gain: str, controller: str) -> Dict[str, object]:
    """Session arguments of a case; with the mechanism off, the gain the shipped rendering uses
    (its derived gain: the seed's own derivation would give a smaller one)."""
    args = dict(GAINS[gain], **CONTROLLER[controller])
    if controller == "off":
        args.setdefault("force_gain", PASSIVE_LIMIT)
    return args


def passes(r: Dict[str, object]) -> bool:
    return r["energy_j"] <= ENERGY_J and r["drift_m"] <= SETTLE_M


COLUMNS = ["grid", "fluid", "gain", "controller+coupling", "force gain", "sim rate (Hz)", "peak energy (mJ)",
           "settle (mm)", "within bounds"]


def run(quick: bool = False) -> dict:
    rows: List[List] = []
    resolutions = (32,) if quick else (32, 48)
    for res in resolutions:
        for fluid, density in FLUIDS.items():
            for gain in GAINS:
                for controller in CONTROLLER:
                    report.progress(f"strokes: {res}^3 {fluid}, {gain} gain, controller {controller}")
                    r = run_strokes(density, resolution=res, **case_args(gain, controller))
                    st = r["stats"]
                    report.progress(f"  gain {st['force_gain']:.4g}, {st['sim_rate_hz']:.1f} Hz, "
                                    f"{1e3 * r['energy_j']:.3f} mJ, {1e3 * r['drift_m']:.3f} mm")
                    rows.append([f"{res}^3", fluid, gain, controller, round(float(st["force_gain"]), 4),
                                 round(float(st["sim_rate_hz"]), 1), round(1e3 * r["energy_j"], 3),
                                 round(1e3 * r["drift_m"], 3), passes(r)])
    notes = ["Quick strokes of the simulated Falcon's hand (300 N/m) in the live demo's geometry (1 m domain, "
             "sphere r 0.08 m, scale 12.5), gravity and source off: six strokes of 3-5 cm in 0.25-0.4 s, "
             "random directions (seed 27), dead stops, 0.4-0.8 s rests, then 2 s of rest.",
             "gain: default = Derive Gain, Amplified; largest = Derive Gain off with Force Gain at the most Start "
             f"accepts without Allow Unsafe Gain, Max Force {UI_MAX_FORCE_N:g} N.",
             "controller+coupling off: the seed's low-passed step force at the same gain, no passivity controller.",
             f"Bounds: peak running energy into the hand <= {1e3 * ENERGY_J:g} mJ, drift from 1 s after the last "
             f"stop <= {1e3 * SETTLE_M:g} mm.",
             "Taken on a shared machine: the simulation's rate depends on the load."]
    return {"title": "Quick strokes: energy into the hand", "columns": COLUMNS, "rows": rows, "notes": notes}


def main(argv: Optional[List[str]] = None) -> int:
    return report.section_main("strokes", run, argv)


if __name__ == "__main__":
    sys.exit(main())
