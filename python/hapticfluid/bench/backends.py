# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``backends`` section: the same steps on the CPU and the GPU backend, side by side.

Scenes (bench/scene.py's plume with a sphere sweeping through it): the seed paper's grid as the
bake runs it (100 x 100 x 70 in a closed box, a step per frame at 24 fps, multigrid CG to a
relative residual of 1e-3), and the live session's grids 32^3 and 48^3 (open top, 30 Hz steps,
multigrid to 1e-3). Each scene runs on the CPU backend with every core, the CPU backend with one
thread, and the GPU backend (here Mesa's llvmpipe when there is no GPU), in rounds that take turns,
so the machine's drift falls on all alike. Per run: wall ms per step (median), CPU ms per step
(this process's, every thread: the pool's or llvmpipe's), steps/s and the share of one core that
a steady rate of them takes, and each stage's median ms (StepReport.gpu_ms: the CPU backend's
wall time per stage). The step's memory floor: a STREAM-like triad measures this machine's
bandwidth, and the step's compulsory traffic is taken as ``BYTES_PER_CELL`` (the study's count
of what the CPU design moves: the pressure solve about 1.16 KB a cell, the other stages about
0.25; shared/reference/reviews/cpu-engine-study-2026-12-04.md).

Run alone: ``python3 -m hapticfluid.bench.backends [--quick] [--json PATH]``.
"""

from __future__ import annotations

import os
import time
from typing import Dict, List, Tuple

import numpy as np

import hapticfluid as hf
from hapticfluid.bench import report
from hapticfluid.bench.scene import SEED_DOMAIN, SEED_RESOLUTION, BenchScene, DemoScene

BYTES_PER_CELL = 1400.0  # the step's compulsory traffic per cell (see the docstring)
TOLERANCE = 1e-3
SCENES = {  # label: (resolution, domain, dt, open top, warm-up steps, timed steps)
    "seed grid, bake (closed)": (SEED_RESOLUTION, SEED_DOMAIN, 1.0 / 24.0, False, 3, 8),
    "32^3, live": ((32, 32, 32), (1.0, 1.0, 1.0), 1.0 / 30.0, True, 6, 40),
    "48^3, live": ((48, 48, 48), (1.0, 1.0, 1.0), 1.0 / 30.0, True, 6, 30),
}
QUICK_SCENES = {"32^3, live": ((32, 32, 32), (1.0, 1.0, 1.0), 1.0 / 30.0, True, 2, 6)}
RUNS = (("CPU backend, all cores", dict(backend="cpu")), ("CPU backend, 1 thread", dict(backend="cpu", cpu_threads=1)),
        ("GPU backend", dict(backend="gpu")))
ROUNDS = 3


def triad_gb_s(mib: int = 384) -> float:
    """A STREAM-like triad (a = b + 3 c) over three float32 arrays of ``mib`` MiB in all: GB/s moved
    (the best of five; numpy's loop on one thread)."""
    n = mib * (1 << 20) // 12
    b = np.ones(n, np.float32)
    c = np.ones(n, np.float32)
    a = np.empty(n, np.float32)
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        np.multiply(c, 3.0, out=a)
        np.add(a, b, out=a)
        best = min(best, time.perf_counter() - t0)
    return 4.0 * n * 4 / best / 1e9  # the two passes move a, b, c and a again


def measure(label: str, spec, kwargs: Dict[str, object]) -> Dict[str, object]:
    resolution, domain, dt, open_top, warm, timed = spec
    scene = BenchScene(resolution, domain, dt_s=dt, physics=DemoScene(open_top=open_top))  # type: ignore[arg-type]
    with scene.make_simulation(pressure_solver="multigrid", pressure_iterations=50, pressure_tolerance=TOLERANCE,
                               compute_residual=False, **kwargs) as sim:
        device = sim.device
        for _ in range(warm):
            scene.step(sim)
        walls: List[float] = []
        stages: Dict[str, List[float]] = {}
        iterations: List[int] = []
        cpu0, t0 = time.process_time(), time.perf_counter()
        for _ in range(timed):
            r = scene.step(sim)
            walls.append(r.wall_ms)
            iterations.append(r.pressure_iterations)
            for name, ms in r.gpu_ms.items():
                stages.setdefault(name, []).append(ms)
        cpu_ms = (time.process_time() - cpu0) * 1000.0 / timed
        elapsed_ms = (time.perf_counter() - t0) * 1000.0 / timed
    return {"scene": label, "cells": scene.cells, "device": device["renderer"], "wall_ms": report.median(walls),
            "elapsed_ms": elapsed_ms, "cpu_ms": cpu_ms, "iterations": float(np.mean(iterations)),
            "stages": {name: report.median(v) for name, v in stages.items()}}


def run(quick: bool = False, log=report.progress) -> dict:
    scenes = QUICK_SCENES if quick else SCENES
    rounds = 1 if quick else ROUNDS
    bandwidth = triad_gb_s(96 if quick else 384)
    results: Dict[Tuple[str, str], List[dict]] = {}
    for r in range(rounds):
        order = list(RUNS) if r % 2 == 0 else list(reversed(RUNS))
        for label, spec in scenes.items():
            for run_label, kwargs in order:
                if log:
                    log(f"backends: round {r + 1}/{rounds}: {label} on the {run_label} ...")
                results.setdefault((label, run_label), []).append(measure(label, spec, kwargs))
    rows, stage_rows, stage_notes = [], [], []
    for (label, run_label), runs in results.items():
        wall = report.median([m["wall_ms"] for m in runs])
        cpu = report.median([m["cpu_ms"] for m in runs])
        cells = runs[0]["cells"]
        floor_ms = BYTES_PER_CELL * cells / (bandwidth * 1e9) * 1000.0
        rows.append([label, run_label, runs[0]["device"], wall, cpu, 1000.0 / wall, cpu / wall,
                     report.median([m["iterations"] for m in runs]), floor_ms, wall / floor_ms])
        per_stage = []
        for stage in runs[0]["stages"]:
            ms = report.median([m["stages"].get(stage, 0.0) for m in runs])
            stage_rows.append([label, run_label, stage, ms, ms * 1e6 / cells])
            if ms >= 0.05:
                per_stage.append(f"{stage} {ms:.2f} ({ms * 1e6 / cells:.1f} ns/cell)")
        stage_notes.append(f"per stage, {label}, {run_label}: " + ", ".join(per_stage))
    notes = [
        f"same process, same scenes, {rounds} rounds taking turns; medians over the rounds of each run's median",
        f"memory floor: {BYTES_PER_CELL:.0f} B per cell per step at the triad's {bandwidth:.1f} GB/s (this machine, "
        f"one thread of numpy)",
        "CPU ms: this process's CPU time per step, every thread; core share = CPU ms / wall ms of a step run "
        "back to back (a steady rate below the maximum costs proportionally less)",
        f"cores: {os.cpu_count()}; CPU backend threads: HAPTICFLUID_CPU_THREADS or one per core",
        "stage ms: StepReport.gpu_ms (the GPU's timer queries; the CPU backend's wall time per stage)",
    ] + stage_notes
    return {"title": "The CPU and the GPU backend, side by side",
            "columns": ["scene", "run", "device", "wall ms/step", "CPU ms/step", "steps/s", "cores busy",
                        "CG it./step", "floor ms", "x floor"],
            "rows": rows, "notes": notes,
            "tables": [{"title": "per stage (median ms; ns per cell)", "columns": ["scene", "run", "stage", "ms",
                                                                             "ns/cell"], "rows": stage_rows}]}


if __name__ == "__main__":
    raise SystemExit(report.section_main("backends", run))
