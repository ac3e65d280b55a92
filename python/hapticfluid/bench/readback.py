# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``readback``: what it costs to get results off the GPU.

- ``force``: the force reduction over the probe's bounding box (the step's ``force`` stage, GL
  timer), which ends in the step's only read-back (``hapticfluid.STEP_READBACK_BYTES``: force, torque,
  centroid, residual and pressure-mean slots); the haptic path needs nothing else.
- ``density``: ``Simulation.density()``, the whole smoke field (a viewport or bake needs it).
- ``velocity``: ``Simulation.velocity()``, the three MAC face fields.

Each on the benchmark scene after a few steps, at 64^3 and 128^3. Times are medians over repeats
of the host call (GPU copy, transfer, numpy array); MB/s is payload bytes over that time.

Run alone: ``python3 -m hapticfluid.bench.readback [--quick] [--json PATH]``.
"""

from __future__ import annotations

import time
from typing import Callable, List, Sequence, Tuple

import numpy as np

import hapticfluid as hf
from hapticfluid.bench import report
from hapticfluid.bench.scene import BenchScene

FULL_GRIDS = ((64, 64, 64), (128, 128, 128))
QUICK_GRIDS = ((16, 16, 16),)
WARMUP_STEPS = 2
FULL_REPEATS = 7
QUICK_REPEATS = 3

COLUMNS = ["grid", "cells", "read-back", "repeats", "ms median", "ms p90", "bytes", "MB/s"]


def _time_call(fn: Callable[[], object], repeats: int) -> Tuple[List[float], int]:
    """Wall ms of each call and the bytes the last call returned."""
    fn()  # first call: allocation of staging buffers, not counted
    times = []
    nbytes = 0
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append((time.perf_counter() - t0) * 1000.0)
        arrays = out if isinstance(out, tuple) else (out,)
        nbytes = int(sum(np.asarray(a).nbytes for a in arrays))
    return times, nbytes


def run(quick: bool = False, grids: Sequence[Tuple[int, int, int]] = (), log=report.progress) -> dict:
    grids = tuple(grids) or (QUICK_GRIDS if quick else FULL_GRIDS)
    repeats = QUICK_REPEATS if quick else FULL_REPEATS
    rows = []
    for res in grids:
        scene = BenchScene(res, (1.0, 1.0, 1.0))
        if log:
            log(f"readback: {scene.label} ...")
        with scene.make_simulation() as sim:
            for _ in range(WARMUP_STEPS):
                scene.step(sim)
            force_ms = []
            for _ in range(repeats):
                r = scene.step(sim)
                force_ms.append(dict(r.gpu_ms)["force"])
            rows.append([scene.label, scene.cells, "force (GPU reduction)", repeats,
                         report.median(force_ms), report.p90(force_ms), hf.STEP_READBACK_BYTES, None])
            for name, fn in (("density()", sim.density), ("velocity()", sim.velocity)):
                times, nbytes = _time_call(fn, repeats)
                med = report.median(times)
                rows.append([scene.label, scene.cells, name, repeats, med, report.p90(times), nbytes,
                             nbytes / 1e6 / (med / 1000.0)])
    notes = [
        "force: GPU time of the step's 'force' stage (face sums over the probe's box, workgroup "
        f"partials reduced on the GPU), which the step then reads back ({hf.STEP_READBACK_BYTES} bytes: "
        "force, torque, centroid, residual, pressure mean; a pressure tolerance > 0 adds the "
        "solver's residual read-backs, not used here)",
        "density()/velocity(): host wall time of the call, GPU texture read-back into a numpy "
        "array (float32); the first call is not counted",
    ]
    return {"title": "Read-back: force reduction and field read-back", "columns": COLUMNS,
            "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("readback", run))
