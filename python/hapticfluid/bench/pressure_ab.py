# SPDX-License-Identifier: GPL-3.0-or-later
"""Before/after of the pressure solve (issue 20): two builds of the ``hapticfluid`` package
stepping the same scene in turns, each in a fresh process, so a machine whose speed drifts
affects both alike. A measurement helper, not a benchmark section.

Per grid and build: the benchmark scene (``BenchScene``: hot plume, sphere probe swinging
through it) with the multigrid solve to a relative residual of 1e-3 every step, the box closed
as in the bake (``--closed``, default for 100x100x70) or open at the top as in the haptic scene;
``WARMUP`` steps, then ``--steps`` steps measured: process CPU time per step (all threads, the
llvmpipe workers included), the step's pressure-stage GPU ms and its probe stages' (voxelize +
classify) GPU ms (``StepReport.gpu_ms``), their medians, and the CG iterations per step. ``--pairs`` rounds, the builds taking turns going first.

Run: ``python3 python/hapticfluid/bench/pressure_ab.py --a DIR_A --b DIR_B --grid 48 48 48``
(DIR: a folder holding a built ``hapticfluid`` package, e.g. ``build/python``). Prints JSON.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from typing import Dict, List

WARMUP = 2
TOLERANCE = 1e-3
MAX_ITERATIONS = 60


def child(grid: List[int], steps: int, closed: bool, iterations: int = 0) -> Dict[str, object]:
    import hapticfluid as hf  # the build under test, from PYTHONPATH
    from hapticfluid.bench.scene import BenchScene

    longest = max(grid)
    scene = BenchScene(tuple(grid), tuple(n / longest for n in grid), dt_s=1.0 / 24.0)  # type: ignore[arg-type]
    kwargs = scene.simulation_kwargs()
    kwargs["open_top"] = not closed
    # iterations > 0: that many CG iterations every step (fixed-count mode), for the cost of one.
    sim = hf.Simulation(**kwargs, pressure_solver="multigrid", pressure_tolerance=0.0 if iterations else TOLERANCE,
                        pressure_iterations=iterations or MAX_ITERATIONS, compute_residual=False)
    p = scene.physics
    sim.set_smoke_source(scene.source_centre_m, scene.source_radius_m, density=p.source_density,
                         temperature=p.source_temperature)
    scene.place_probe(sim, 0.0)
    cpu, gpu, probe, its, res = [], [], [], [], []
    try:
        for n in range(WARMUP + steps):
            c0 = time.process_time()
            r = scene.step(sim)
            c1 = time.process_time()
            if n >= WARMUP:
                cpu.append((c1 - c0) * 1000.0)
                gpu.append(float(r.gpu_ms.get("pressure", float("nan"))))
                probe.append(float(r.gpu_ms.get("voxelize", 0.0) + r.gpu_ms.get("classify", 0.0)))
                its.append(r.pressure_iterations)
                res.append(r.relative_residual)
                if not iterations and not r.converged:
                    raise RuntimeError(f"step {n}: the solve stopped at {r.relative_residual:g}")
    finally:
        sim.close()
    return {"cpu_ms": cpu, "pressure_gpu_ms": gpu, "probe_gpu_ms": probe, "iterations": its, "residual": res}


def run_build(package: str, grid: List[int], steps: int, closed: bool, iterations: int = 0) -> Dict[str, object]:
    env = dict(os.environ)
    env["PYTHONPATH"] = package
    cmd = [sys.executable, os.path.abspath(__file__), "--child", "--grid", *map(str, grid), "--steps", str(steps),
           "--iterations", str(iterations)]
    if closed:
        cmd.append("--closed")
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=3600, cwd="/")
    if out.returncode != 0:
        raise RuntimeError(f"{package}: exit {out.returncode}\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", action="store_true")
    ap.add_argument("--a", help="folder of build A (before)")
    ap.add_argument("--b", help="folder of build B (after)")
    ap.add_argument("--grid", type=int, nargs=3, required=True)
    ap.add_argument("--steps", type=int, default=6)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--closed", action="store_true")
    ap.add_argument("--iterations", type=int, default=0, help="fixed CG iterations per step (0: to 1e-3)")
    a = ap.parse_args(argv)
    if a.child:
        print(json.dumps(child(a.grid, a.steps, a.closed, a.iterations)))
        return 0
    rounds = []
    for k in range(a.pairs):
        order = [("a", a.a), ("b", a.b)] if k % 2 == 0 else [("b", a.b), ("a", a.a)]
        rnd = {}
        for name, pkg in order:
            r = run_build(pkg, a.grid, a.steps, a.closed, a.iterations)
            rnd[name] = {"cpu_ms_median": statistics.median(r["cpu_ms"]), "cpu_ms_min": min(r["cpu_ms"]),
                         "pressure_gpu_ms_median": statistics.median(r["pressure_gpu_ms"]),
                         "pressure_gpu_ms_min": min(r["pressure_gpu_ms"]),
                         "probe_gpu_ms_median": statistics.median(r["probe_gpu_ms"]),
                         "iterations_mean": sum(r["iterations"]) / len(r["iterations"]),
                         "worst_residual": max(r["residual"])}
            print(json.dumps({"pair": k + 1, "build": name, **rnd[name]}), file=sys.stderr, flush=True)
        rounds.append(rnd)
    summary = {}
    for name in ("a", "b"):
        summary[name] = {key: statistics.median(r[name][key] for r in rounds)
                         for key in ("cpu_ms_median", "cpu_ms_min", "pressure_gpu_ms_median", "pressure_gpu_ms_min",
                                     "probe_gpu_ms_median", "iterations_mean")}
    print(json.dumps({"grid": a.grid, "closed": a.closed, "steps": a.steps, "iterations": a.iterations, "a": a.a, "b": a.b,
                      "rounds": rounds, "median_of_rounds": summary}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
