# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``engine``: steps per second and GPU milliseconds per stage of the whole
simulation step, on the benchmark scene (plume + moving sphere probe, vorticity confinement),
at 64^3, the seed paper's 100 x 100 x 70, 128^3 and 256^3, for every pressure solver in
``SOLVERS``.

Per grid and solver: warm-up steps first (the first step compiles shaders), not counted; then
steps until ``max_steps`` or the time budget, whichever comes first (at least ``min_steps``).
Wall ms is the host time of ``Simulation.step`` (median and 90th percentile); GPU ms per stage
are the median of the engine's GL timer queries (``StepReport.gpu_ms``); the relative residual
is the median of ``||rhs - A p|| / ||rhs||`` after each measured step's pressure solve.

Run alone: ``python3 -m hapticfluid.bench.engine [--quick] [--json PATH]``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import hapticfluid as hf
from hapticfluid import _core
from hapticfluid.bench import report
from hapticfluid.bench.scene import SEED_DOMAIN, SEED_RESOLUTION, BenchScene

# Pressure solvers to compare: (label, Simulation keyword arguments). A new solver is one line.
SOLVERS: List[Tuple[str, Dict[str, object]]] = [
    ("jacobi-40", {"pressure_iterations": 40}),
    ("multigrid-4", {"pressure_solver": "multigrid", "pressure_iterations": 4}),
    # The GPU goal's solve (issue 20): warm-started multigrid CG to a relative residual of 1e-4,
    # at most 30 iterations ("pressure iterations" is then the median over the timed steps).
    ("multigrid-1e-4", {"pressure_solver": "multigrid", "pressure_iterations": 30, "pressure_tolerance": 1e-4}),
]


@dataclass(frozen=True)
class Size:
    resolution: Tuple[int, int, int]
    domain_size: Tuple[float, float, float]
    warmup: int  # steps run before measuring (shader compilation, warm start)
    min_steps: int
    max_steps: int
    budget_s: float  # stop measuring once this much wall time is spent (after min_steps)


FULL_SIZES = (
    Size((64, 64, 64), (1.0, 1.0, 1.0), warmup=3, min_steps=10, max_steps=40, budget_s=15.0),
    Size(SEED_RESOLUTION, SEED_DOMAIN, warmup=2, min_steps=6, max_steps=30, budget_s=20.0),
    Size((128, 128, 128), (1.0, 1.0, 1.0), warmup=2, min_steps=4, max_steps=20, budget_s=25.0),
    # On a software device a 256^3 step takes tens of seconds: few steps, said in the notes.
    Size((256, 256, 256), (1.0, 1.0, 1.0), warmup=1, min_steps=3, max_steps=10, budget_s=30.0),
)
QUICK_SIZES = (
    Size((16, 16, 16), (1.0, 1.0, 1.0), warmup=1, min_steps=3, max_steps=3, budget_s=5.0),
    Size((20, 20, 14), SEED_DOMAIN, warmup=1, min_steps=3, max_steps=3, budget_s=5.0),
)

# Use at most this share of the device's memory (a software device shares it with the host).
MEMORY_SHARE = 0.5

FIXED_COLUMNS = ["grid", "cells", "solver", "steps", "steps/s", "wall ms median", "wall ms p90",
                 "GPU ms total", "dispatches/step", "GPU->CPU syncs/step"]


def available_memory_bytes(device_info: Dict[str, object]) -> Optional[int]:
    """Memory a grid may use: the device's, and for a software device also what the host has free."""
    limits = []
    mem = device_info.get("memory_bytes")
    if isinstance(mem, int) and mem > 0:
        limits.append(mem)
    if device_info.get("software"):
        try:
            with open("/proc/meminfo", encoding="utf-8") as f:
                for line in f:
                    if line.startswith("MemAvailable:"):
                        limits.append(int(line.split()[1]) * 1024)
        except (OSError, ValueError, IndexError):
            pass
    return min(limits) if limits else None


@dataclass
class Measurement:
    scene: BenchScene
    solver: str
    wall_ms: List[float]
    gpu_ms: List[Dict[str, float]]
    residuals: List[float]
    iterations: List[int]  # the pressure solve's iterations, per timed step
    dispatches_per_step: float = 0.0  # compute dispatches per timed step (gl_counters)
    syncs_per_step: float = 0.0       # GPU-to-CPU read-backs per timed step

    def stage_names(self) -> List[str]:
        names: List[str] = []
        for step in self.gpu_ms:
            for name in step:
                if name not in names:
                    names.append(name)
        return names

    def stage_median(self, name: str) -> Optional[float]:
        values = [step[name] for step in self.gpu_ms if name in step]
        return report.median(values) if values else None

    def gpu_total_median(self) -> float:
        return report.median([sum(step.values()) for step in self.gpu_ms])


def measure(scene: BenchScene, solver: str, solver_kwargs: Dict[str, object], size: Size) -> Measurement:
    """Run warm-up steps, then timed steps, of ``scene`` with one pressure solver."""
    with scene.make_simulation(**solver_kwargs) as sim:
        for _ in range(size.warmup):
            scene.step(sim)
        wall: List[float] = []
        gpu: List[Dict[str, float]] = []
        residuals: List[float] = []
        iterations: List[int] = []
        before = _core.gl_counters()
        start = time.perf_counter()
        while len(wall) < size.max_steps:
            if len(wall) >= size.min_steps and time.perf_counter() - start >= size.budget_s:
                break
            r = scene.step(sim)
            wall.append(r.wall_ms)
            gpu.append(dict(r.gpu_ms))
            iterations.append(r.pressure_iterations)
            if r.relative_residual >= 0.0:
                residuals.append(r.relative_residual)
        after = _core.gl_counters()
    steps = max(len(wall), 1)
    return Measurement(scene, solver, wall, gpu, residuals, iterations,
                       (after["dispatches"] - before["dispatches"]) / steps,
                       (after["syncs"] - before["syncs"]) / steps)


def run(quick: bool = False, sizes: Optional[Sequence[Size]] = None,
        solvers: Optional[Sequence[Tuple[str, Dict[str, object]]]] = None,
        log=report.progress) -> dict:
    sizes = tuple(sizes) if sizes is not None else (QUICK_SIZES if quick else FULL_SIZES)
    solvers = list(solvers) if solvers is not None else SOLVERS
    device = hf.probe_device()
    memory = available_memory_bytes(device)
    notes: List[str] = []
    results: List[Measurement] = []
    for size in sizes:
        scene = BenchScene(size.resolution, size.domain_size)
        need = hf.estimate_bytes(size.resolution)
        if memory is not None and need > MEMORY_SHARE * memory:
            notes.append(f"{scene.label} skipped: its fields need {need / 2**20:.0f} MiB, more than "
                         f"{MEMORY_SHARE:.0%} of the {memory / 2**20:.0f} MiB available")
            continue
        for label, kwargs in solvers:
            if log:
                log(f"engine: {scene.label} {label} ...")
            m = measure(scene, label, kwargs, size)
            results.append(m)
            if len(m.wall_ms) < size.max_steps:
                notes.append(f"{scene.label} {label}: {len(m.wall_ms)} timed steps (time budget "
                             f"{size.budget_s:.0f} s; {size.warmup} warm-up)")
    stages: List[str] = []
    for m in results:
        for name in m.stage_names():
            if name not in stages:
                stages.append(name)
    columns = FIXED_COLUMNS + [f"{s} ms" for s in stages] + ["pressure iterations", "rel. residual"]
    rows = []
    for m in results:
        total_s = sum(m.wall_ms) / 1000.0
        row = [m.scene.label, m.scene.cells, m.solver, len(m.wall_ms), len(m.wall_ms) / total_s,
               report.median(m.wall_ms), report.p90(m.wall_ms), m.gpu_total_median(),
               m.dispatches_per_step, m.syncs_per_step]
        row += [report.finite_or_none(m.stage_median(s)) for s in stages]
        row += [report.median(m.iterations) if m.iterations else None, report.finite_or_none(report.median(m.residuals)) if m.residuals else None]
        rows.append(row)
    scene0 = BenchScene(sizes[0].resolution, sizes[0].domain_size) if sizes else None
    notes += [
        f"scene: smoke plume (source {scene0.physics.source_temperature:g} K, heat buoyancy "
        f"{scene0.physics.heat_buoyancy:g} m/s^2/K, vorticity {scene0.physics.vorticity:g}), open top, "
        f"sphere probe (radius {scene0.physics.probe_radius:g} of the box) sweeping x "
        f"+-{scene0.sweep_amplitude:g} box widths every {scene0.sweep_period_s:g} s; "
        f"dt {scene0.dt_s:.4g} s" if scene0 else "no sizes",
        f"wall ms: host time of Simulation.step (includes its {hf.STEP_READBACK_BYTES}-byte result read-back); "
        "GPU ms: GL timestamp queries around each stage, median over the timed steps",
        "dispatches/step and GPU->CPU syncs/step: compute dispatches and read-backs that wait for the GPU, "
        "mean over the timed steps (the scene's probe pose upload and result read-back included)",
        f"device: {device.get('renderer')} ({device.get('version')})",
    ]
    if device.get("warning"):
        notes.append(f"device warning: {device['warning']}")
    if device.get("software"):
        notes.append("software rasterizer (llvmpipe): 'GPU' times are CPU times of the shader threads")
    return {"title": "Engine: full simulation step", "columns": columns, "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("engine", run))
