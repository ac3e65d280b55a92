# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: what a hand feels in the live demo's default scene (issue 27).

The add-on's live demo (scripts/live_demo.py): a 1 m domain of air (1.2 kg/m^3, gravity), a hot
smoke source at its floor, a sphere probe of r = 0.08 m, 32^3 cells, every fluid and haptic
setting at the add-on's default, the simulated Falcon's workspace fitted to the domain (scale
12.5) and its hand doing the ``sweep`` gesture (hapticfluid.hand_gestures). For each rendering
(the seed's low-passed step force at its derived gain; the virtual coupling at the amplified
default gain; physical 1:1 forces) it records every haptic period and reports the force on the
hand (peak, RMS), in the plume against beside it, its x component moving +x against -x (it must
reverse with the motion), and the energy the device delivered to the hand.

Run alone: ``python3 -m hapticfluid.bench.feel [--quick] [--json PATH]``.
"""

from __future__ import annotations

import logging
import sys
import time
from typing import Callable, Dict, List, Optional

import numpy as np

import hapticfluid as hf
from hapticfluid import hand_gestures
from hapticfluid.bench import report

log = logging.getLogger("hapticfluid.bench.feel")

COLUMNS = ["rendering", "seconds", "gain", "sim rate (Hz)", "hand peak (N)", "hand RMS (N)", "probe peak (N)",
           "in plume |F| (N)", "beside |F| (N)", "Fx moving +x (N)", "Fx moving -x (N)", "max energy into hand (mJ)"]
PLUME_HALF_WIDTH_M = 0.12   # domain m either side of the source's axis (x = 0.5) counted as the plume
BESIDE_M = 0.2              # domain m from the axis beyond which the probe is beside the plume
MAX_FORCE_N = 4.0           # the add-on's default Max Force
SCENE = {"fluid_density": 1.2, "gravity": (0.0, 0.0, -9.81), "open_top": True, "vorticity": 0.4,
         "heat_buoyancy": 1.0, "smoke_dissipation": 0.05, "heat_dissipation": 0.4, "pressure_iterations": 40,
         "pressure_solver": "multigrid", "pressure_tolerance": 1e-3}  # the add-on's defaults (object_props.py)


PASSIVE_LIMIT = "passive limit"  # force_gain of live_scene_run: the largest given gain Start accepts


def passive_limit(sim, device, session_args) -> float:
    """The largest Force Gain (Derive Gain off) a session with these settings accepts without
    allow_unsafe_gain: the gain the engine derives for Amplified feel with the rendering as
    shipped, virtual coupling and passivity controller on (haptic_session.cpp)."""
    args = dict(session_args, force_gain=None, feel="amplified", allow_unsafe_gain=False, coupling=True,
                passivity=True)
    return float(hf.HapticSession(sim, device, **args).stats()["force_gain"])


def live_scene_run(seconds: float, resolution: int = 32, gesture: str = "sweep", fluid_density: float = 1.2,
                   hand_stiffness: float = 300.0, hand_path=None, gravity=None, source: bool = True,
                   until: Optional[Callable[[Dict[str, np.ndarray]], bool]] = None,
                   **session_args) -> Dict[str, object]:
    """One session of the live demo's scene for `seconds` (s) with the simulated Falcon's hand doing
    `gesture` (or following hand_path: waypoints (t, x, y, z) after homing, held at the last):
    the trace (time, position, sim_force, commanded_force, ...) and the session's stats. gravity
    (m/s^2) and source=False change the scene (no steady forces: the rendering's own energy).
    until: called with each new part of the trace (times on the monotonic clock, every 0.05 s);
    the run ends as soon as it returns True, `seconds` being then the longest it may take (a test
    paced by the simulation's own clock, whatever the machine's load)."""
    scene = dict(SCENE, fluid_density=fluid_density)
    if gravity is not None:
        scene["gravity"] = tuple(gravity)
    hand = hand_gestures.falcon_args(gesture) if hand_path is None else {"hand_path": hand_path, "hand_loop": False}
    # the add-on opens the device with its Max Force too
    falcon = hf.open_simulated_falcon(max_force=session_args.get("max_force", MAX_FORCE_N),
                                      hand_stiffness=hand_stiffness, **hand)
    try:
        info = falcon.info()
        scale = float(min(1.0 / (info.workspace_max[i] - info.workspace_min[i]) for i in range(3)))
        with hf.Simulation(resolution=(resolution,) * 3, domain_size=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0),
                           compute_residual=False, **scene) as sim:
            if source:
                sim.set_smoke_source((0.5, 0.5, 0.14), 0.08, density=1.0, temperature=8.0)
            sim.set_probe((0.28, 0.5, 0.55), 0.08)
            args = dict(workspace_scale=scale, filter="lowpass", max_force=MAX_FORCE_N, probe_radius=None)
            args.update(session_args)
            if args.get("force_gain") == PASSIVE_LIMIT:  # the add-on's Force Gain at the most Start accepts
                args["force_gain"] = passive_limit(sim, falcon, args)
            session = hf.HapticSession(sim, falcon, trace=True, trace_seconds=seconds + 5.0, **args)
            chunks = []
            with session:
                start = time.monotonic()
                while time.monotonic() - start < seconds and session.error is None:
                    time.sleep(0.05)
                    chunks.append(session.trace())
                    if until is not None and len(chunks[-1]["time"]) and until(chunks[-1]):
                        break
                stats = session.stats()
            chunks.append(session.trace())
    finally:
        falcon.close()
    trace = {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}
    t0 = trace["time"][0]
    trace["time"] = trace["time"] - t0
    # The pose time of the step each period's force came from, on the same clock (NaN before the first).
    trace["step_pose_time"] = np.where(trace["step_pose_time"] > 0.0, trace["step_pose_time"] - t0, np.nan)
    return {"trace": trace, "stats": stats, "scale": scale}


def energy_into_hand(trace: Dict[str, np.ndarray]) -> np.ndarray:
    """Running energy the device delivered to the hand, sum F(k-1) . (x(k) - x(k-1)) (J, per period)."""
    x, f = trace["position"], trace["commanded_force"]
    return np.concatenate([[0.0], np.cumsum(np.sum(f[:-1] * np.diff(x, axis=0), axis=1))])


def feel_figures(run: Dict[str, object], settle_s: float = 3.0, late: Optional[np.ndarray] = None) -> Dict[str, float]:
    """The hand's force in a run of live_scene_run: after settle_s (the force ramped in, the plume
    risen), its peak and RMS magnitude, mean magnitude in the plume and beside it, mean x component
    moving +x and -x (device frame), the probe's peak (fluid N) and the most energy delivered.
    late: the periods to count instead (a mask over the trace)."""
    tr, scale = run["trace"], run["scale"]
    t, x, f = tr["time"], tr["position"], tr["commanded_force"]
    late = t >= settle_s if late is None else late
    mag = np.linalg.norm(f, axis=1)
    domain_x = 0.5 + scale * x[:, 0]  # the workspace's middle is at the domain's centre
    vx = np.gradient(x[:, 0], t)
    moving = np.abs(vx) > 0.005  # m/s, device frame
    plume = late & moving & (np.abs(domain_x - 0.5) < PLUME_HALF_WIDTH_M)
    beside = late & moving & (np.abs(domain_x - 0.5) > BESIDE_M)
    e = energy_into_hand(tr)

    def mean(a):
        return float(np.mean(a)) if len(a) else float("nan")

    return {"hand_peak_n": float(mag[late].max()), "hand_rms_n": float(np.sqrt(np.mean(mag[late] ** 2))),
            "probe_peak_n": float(np.linalg.norm(tr["sim_force"][late], axis=1).max()),
            "plume_n": mean(mag[plume]), "beside_n": mean(mag[beside]),
            "fx_plus_n": mean(f[late & (vx > 0.005), 0]), "fx_minus_n": mean(f[late & (vx < -0.005), 0]),
            "max_energy_mj": float(1e3 * e.max())}


RENDERINGS = {"seed (low-passed step force)": {"coupling": False},
              "coupling, amplified (default)": {},
              "coupling, physical 1:1": {"feel": "physical"}}


def run(quick: bool = False) -> dict:
    seconds = 6.0 if quick else 12.0
    rows: List[List] = []
    for name, args in RENDERINGS.items():
        report.progress(f"feel: {name}, {seconds:g} s")
        r = live_scene_run(seconds, **args)
        fig = feel_figures(r)
        st = r["stats"]
        rows.append([name, seconds, round(float(st["force_gain"]), 4), round(float(st["sim_rate_hz"]), 1)]
                    + [round(fig[k], 4) for k in ("hand_peak_n", "hand_rms_n", "probe_peak_n", "plume_n", "beside_n",
                                                  "fx_plus_n", "fx_minus_n", "max_energy_mj")])
    notes = ["The live demo's scene: 1 m air domain, smoke source at the floor, sphere probe r 0.08 m, 32^3, "
             "simulated Falcon (300 N/m hand) sweeping x +-2.5 cm every 3 s, workspace fitted (scale 12.5), "
             f"max_force {MAX_FORCE_N:g} N; figures after the first 3 s (ramp-in, plume rising).",
             f"In plume: probe within {PLUME_HALF_WIDTH_M:g} m of the source's axis while moving; beside: "
             f"beyond {BESIDE_M:g} m. Fx: device frame, mean while the hand moves +x or -x.",
             "Energy: the running sum F(k-1).(x(k)-x(k-1)) into the hand, its largest value (mJ).",
             "Taken on a shared machine: the simulation's rate depends on the load."]
    return {"title": "What the hand feels in the live demo's scene", "columns": COLUMNS, "rows": rows, "notes": notes}


def main(argv: Optional[List[str]] = None) -> int:
    return report.section_main("feel", run, argv)


if __name__ == "__main__":
    sys.exit(main())
