# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``floor``: the least a step can cost on this device, from what it launches.

A step is a list of compute dispatches; on Mesa's llvmpipe every launched invocation costs CPU
time even when it does nothing. This section measures that cost
(``_core.measure_dispatch_floor``: dispatches over the step's grid whose invocations do nothing,
then ones that store one texel each) and counts what a step launches (``_core.gl_counters``:
dispatches and invocations over the timed steps). Their product is a floor for the step on this
device whatever its shaders compute: the step's invocations at the empty cost, and at the cost
with one store each (every stage writes its cells once).

Scenes: the bake benchmark's step (``mantaflow_bake``'s scene: 100 x 100 x 70 in a closed box,
dt 1/24 s, multigrid CG to 1e-3 every step) and the benchmark scene at 48^3 (the haptic goal's
grid, open top) with the same solve.

Run alone: ``python3 -m hapticfluid.bench.floor [--quick] [--json PATH]``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import List, Optional, Sequence

import hapticfluid as hf
from hapticfluid import _core
from hapticfluid.bench import mantaflow_bake, report
from hapticfluid.bench.scene import BenchScene

COLUMNS = ["scene", "grid", "CG iterations/step", "dispatches/step", "M invocations/step",
           "grid passes/step", "empty ns/inv (wall)", "empty ns/inv (CPU)", "store ns/inv (wall)",
           "store ns/inv (CPU)", "floor ms/step (empty, wall)", "floor ms/step (store, wall)",
           "step ms (wall)", "step ms (CPU)", "store floor / step"]

SOLVE = {"pressure_solver": "multigrid", "pressure_iterations": mantaflow_bake.MAX_ITERATIONS,
         "pressure_tolerance": mantaflow_bake.TOLERANCE}
FLOOR_REPEATS = 20
QUICK_FLOOR_REPEATS = 3


@dataclass(frozen=True)
class FloorScene:
    label: str
    scene: BenchScene
    open_top: bool
    warmup: int
    steps: int


def scenes(quick: bool) -> Sequence[FloorScene]:
    if quick:
        return (FloorScene("bake scene (closed box)", mantaflow_bake.bench_scene(20), False, 1, 2),
                FloorScene("bench scene (open top)", BenchScene((16, 16, 16), (1.0, 1.0, 1.0)), True, 1, 2))
    return (FloorScene("bake scene (closed box)", mantaflow_bake.bench_scene(100), False, 2, 6),
            FloorScene("bench scene (open top)", BenchScene((48, 48, 48), (1.0, 1.0, 1.0)), True, 3, 10))


def measure(fs: FloorScene, repeats: int) -> List[Optional[float]]:
    """One row: the scene's launched work per step, the floor per invocation, their products."""
    res = fs.scene.resolution
    cells = res[0] * res[1] * res[2]
    with fs.scene.make_simulation(open_top=fs.open_top, **SOLVE) as sim:
        for _ in range(fs.warmup):
            fs.scene.step(sim)
        before = _core.gl_counters()
        cpu0, wall0 = time.process_time(), time.perf_counter()
        iterations = [fs.scene.step(sim).pressure_iterations for _ in range(fs.steps)]
        cpu_ms = (time.process_time() - cpu0) * 1000.0 / fs.steps
        wall_ms = (time.perf_counter() - wall0) * 1000.0 / fs.steps
        after = _core.gl_counters()
    dispatches = (after["dispatches"] - before["dispatches"]) / fs.steps
    invocations = (after["invocations"] - before["invocations"]) / fs.steps
    floor = _core.measure_dispatch_floor(res, repeats)
    empty_ms = invocations * floor["empty_wall_ns"] * 1e-6
    store_ms = invocations * floor["store_wall_ns"] * 1e-6
    return [fs.label, "x".join(str(n) for n in res), sum(iterations) / len(iterations), dispatches,
            invocations / 1e6, invocations / cells, floor["empty_wall_ns"], floor["empty_cpu_ns"],
            floor["store_wall_ns"], floor["store_cpu_ns"], empty_ms, store_ms, wall_ms, cpu_ms,
            store_ms / wall_ms if wall_ms > 0 else None]


def run(quick: bool = False, log=report.progress) -> dict:
    repeats = QUICK_FLOOR_REPEATS if quick else FLOOR_REPEATS
    rows = []
    for fs in scenes(quick):
        if log:
            log(f"floor: {fs.label} {fs.scene.label} ...")
        rows.append(measure(fs, repeats))
    device = hf.probe_device()
    notes = [
        f"solve: multigrid CG to a relative residual of {mantaflow_bake.TOLERANCE:g} every step "
        f"(at most {mantaflow_bake.MAX_ITERATIONS} iterations), the bake benchmark's",
        "invocations: workgroups x local size of every dispatch of the timed steps "
        "(padding of partial workgroups included); grid passes = invocations / cells",
        f"ns/inv: median of {repeats} dispatches over the scene's grid, each to glFinish; empty = "
        "invocations that do nothing, store = each stores one R32F texel; CPU = this process's CPU "
        "time (llvmpipe's shader threads included)",
        "floor ms/step = invocations/step x ns/inv: what launching the step's invocations costs "
        "before its shaders do any work (store: with one write per invocation)",
        "step ms: the scene's Simulation.step (its result read-back included), mean of the timed steps",
        f"device: {device.get('renderer')} ({device.get('version')})",
    ]
    return {"title": "Floor: the step's launched invocations at the device's cost per invocation",
            "columns": COLUMNS, "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("floor", run))
