# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: the haptic loop's rate, period jitter and pose-to-force latency.

Scenarios: the loop idle (session paused: no simulation work beside it) and with a simulation
running beside it (64^3 smoke scene, a scripted device sweeping the probe through it), each
with and without SCHED_FIFO priority. Then the interactive rate with the converged solver
(multigrid CG to a relative residual of ``CONVERGED_TOLERANCE`` every step, the moving sphere,
the same smoke scene) at ``CONVERGED_GRIDS``: the simulation steps per second a user touching
it gets, and the pose-to-force latency. Jitter is |period - 1 ms|; latency runs from the device
read whose pose a simulation step used to the first haptic period that applies that step's force.

Run alone: ``python3 -m hapticfluid.bench.haptic [--quick] [--json PATH]``.
"""

from __future__ import annotations

import os
import sys
import time
from typing import Dict, List, Optional

import hapticfluid as hf
from hapticfluid import haptic_cli
from hapticfluid.bench import report

COLUMNS = ["scenario", "grid", "priority", "seconds", "loop rate (Hz)", "jitter p50 (ms)",
           "jitter p99 (ms)", "jitter max (ms)", "skipped periods", "sim rate (Hz)",
           "latency p50 (ms)", "latency p99 (ms)", "latency max (ms)"]


CONVERGED_TOLERANCE = 1e-3
CONVERGED_MAX_ITERATIONS = 50
CONVERGED_GRIDS = (32, 48, 64)
QUICK_CONVERGED_GRIDS = (16,)


def _smoke_simulation(n: int, **solver) -> hf.Simulation:
    sim = hf.Simulation(resolution=(n, n, n), fluid_density=1000.0, gravity=(0.0, 0.0, 0.0), **solver)
    sim.set_smoke_source(centre=(0.5, 0.5, 0.1), radius=0.08, density=1.0, temperature=10.0)
    sim.heat_buoyancy = 0.5
    return sim


def _measure(sim: hf.Simulation, seconds: float, realtime: bool, paused: bool) -> Dict[str, object]:
    times, positions = haptic_cli.sweep_waypoints()
    device = hf.scripted_device(times, positions, loop=True)
    session = hf.HapticSession(sim, device, workspace_scale=6.0, probe_radius=0.1,
                               realtime=realtime, ramp_time=0.5)
    with session:
        if paused:
            session.pause()
        time.sleep(seconds)
        stats = session.stats()
    device.close()
    return stats


def _row(name: str, grid: str, seconds: float, stats: Dict[str, object], sim_running: bool) -> List:
    def r(x: object, digits: int = 3) -> Optional[float]:
        return round(float(x), digits) if x is not None else None

    priority = "SCHED_FIFO" if stats["realtime"] else "normal"
    latency = sim_running and stats["latency_samples"] > 0
    return [name, grid, priority, seconds, r(stats["haptic_rate_hz"], 1), r(stats["jitter_p50_ms"]),
            r(stats["jitter_p99_ms"]), r(stats["jitter_max_ms"]), stats["skipped_periods"],
            r(stats["sim_rate_hz"], 2) if sim_running else None,
            r(stats["latency_p50_ms"], 1) if latency else None,
            r(stats["latency_p99_ms"], 1) if latency else None,
            r(stats["latency_max_ms"], 1) if latency else None]


def run(quick: bool = False) -> dict:
    """Measure each scenario; quick=True uses shorter runs and a 32^3 grid (under ~20 s)."""
    idle_s, busy_s, n = (1.0, 3.0, 32) if quick else (5.0, 15.0, 64)
    rows: List[List] = []
    notes: List[str] = []
    scheduling = ""
    with _smoke_simulation(n, pressure_iterations=40) as sim:
        renderer = sim.device["renderer"]
        for realtime in (True, False):
            stats = _measure(sim, idle_s, realtime, paused=True)
            rows.append(_row("idle (paused)", "-", idle_s, stats, False))
            scheduling = scheduling or (stats["scheduling"] if realtime else "")
            stats = _measure(sim, busy_s, realtime, paused=False)
            rows.append(_row("simulation running", f"{n}^3", busy_s, stats, True))
            scheduling = scheduling or (stats["scheduling"] if realtime else "")
    label = f"converged solver (multigrid to {CONVERGED_TOLERANCE:g})"
    for m in (QUICK_CONVERGED_GRIDS if quick else CONVERGED_GRIDS):
        with _smoke_simulation(m, pressure_solver="multigrid", pressure_iterations=CONVERGED_MAX_ITERATIONS,
                               pressure_tolerance=CONVERGED_TOLERANCE) as sim:
            stats = _measure(sim, busy_s, True, paused=False)
        rows.append(_row(label, f"{m}^3", busy_s, stats, True))
    notes.append(f"GL renderer: {renderer}; {os.cpu_count()} CPUs; load average before: "
                 f"{', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    notes.append("Nominal period 1 ms; jitter = |measured period - 1 ms| over the last 8192 periods.")
    notes.append("Latency: device read -> first haptic period applying the force computed from that "
                 "pose (includes waiting for the running step, the step itself and the next period).")
    if scheduling:
        notes.append(f"SCHED_FIFO: {scheduling}")
    notes.append(f"'{label}': the same scene and sweep, the pressure solve to a relative residual of "
                 f"{CONVERGED_TOLERANCE:g} every step (at most {CONVERGED_MAX_ITERATIONS} CG iterations), "
                 "SCHED_FIFO asked for; sim rate = simulation steps per second beside the haptic loop.")
    notes.append("Taken on a shared machine: figures are under load unless said otherwise.")
    return {"title": "Haptic loop: rate, jitter, pose-to-force latency", "columns": COLUMNS,
            "rows": rows, "notes": notes}


def main(argv: Optional[List[str]] = None) -> int:
    """Run alone: the same command line and JSON document (schema, machine, sections; written
    atomically, NaN refused) as every other section."""
    return report.section_main("haptic", run, argv)


if __name__ == "__main__":
    sys.exit(main())
