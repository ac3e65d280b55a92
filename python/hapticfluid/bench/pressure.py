# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section "pressure": Jacobi against multigrid-preconditioned CG.

For each grid, identical simulations (a sphere probe moving through a rising hot plume in a
box open at the top, the state after a few steps solved tightly) take one more step, each
with one solver in tolerance mode: the pressure solve runs until the relative residual
||rhs - A p|| / ||rhs|| is at most 1e-4 (warm-started from the previous step's pressure, as in
the simulation). Reported per solver and grid: iterations (Jacobi sweeps; CG iterations, one
V-cycle each), time of the pressure stage (GPU timer, ms), ms per iteration, the residual
reached, and the mean convergence factor per iteration (final / initial residual)^(1 / n).

Jacobi needs of the order of 1e5 sweeps at 128^3 (over an hour on llvmpipe); it runs at most
JACOBI_SWEEPS[grid] sweeps. If that does not reach the tolerance, a second run with half
as many gives the rate of the last half, and the sweeps to the tolerance are extrapolated at
that rate (marked "extrapolated"). Jacobi's rate only slows as its slowest modes take over, so
an extrapolation underestimates its time: the ratio it gives is a lower bound.

The box is open at the top: in a closed box plain Jacobi does not converge at all (its
iteration matrix has the eigenvalue -1, the checkerboard mode, besides the constant), so
there is no time to the tolerance to compare.

Run alone: ``python3 -m hapticfluid.bench.pressure [--quick] [--json PATH]``.
"""

from __future__ import annotations

import math
import os
import sys
from typing import Dict, List, Sequence, Tuple

import hapticfluid as hf
from hapticfluid.bench import report

TOLERANCE = 1e-4
FULL_GRIDS: Tuple[Tuple[int, int, int], ...] = ((64, 64, 64), (100, 100, 70), (128, 128, 128))
QUICK_GRIDS: Tuple[Tuple[int, int, int], ...] = ((16, 16, 16), (24, 24, 16))
WARMUP_STEPS = 3
DT_S = 0.02
MULTIGRID_MAX_ITERATIONS = 200
# Jacobi sweeps run at most, per grid (see the module docstring).
JACOBI_SWEEPS = {(16, 16, 16): 3000, (24, 24, 16): 1500, (64, 64, 64): 40000, (100, 100, 70): 15000,
                 (128, 128, 128): 15000}

COLUMNS = ["grid", "solver", "iterations", "pressure_ms", "ms_per_iteration", "initial_residual",
           "reached_residual", "convergence_factor", "time_to_tolerance_ms", "how"]


def _scene(resolution: Sequence[int]) -> hf.Simulation:
    """A sphere probe moving through a hot plume in a closed box of cubic cells (longest edge 1 m)."""
    longest = max(resolution)
    size = tuple(n / longest for n in resolution)
    sim = hf.Simulation(resolution=tuple(resolution), domain_size=size, gravity=(0.0, 0.0, -9.81),
                        heat_buoyancy=4.0, fluid_density=1.2, open_top=True, pressure_solver="multigrid",
                        pressure_tolerance=1e-5, pressure_iterations=MULTIGRID_MAX_ITERATIONS)
    sim.set_smoke_source((0.5 * size[0], 0.5 * size[1], 0.15 * size[2]), 0.08 * size[2], density=1.0,
                         temperature=2.0)
    return sim


def _probe_at(sim: hf.Simulation, step: int) -> None:
    size = sim.domain_size
    x = 0.3 * size[0] + 0.3 * DT_S * step
    sim.set_probe((x, 0.45 * size[1], 0.55 * size[2]), 0.12 * size[2], velocity=(0.3, 0.0, 0.1))


def _solve(resolution: Sequence[int], solver: str, iterations: int) -> hf.StepReport:
    """The measured step of a fresh scene: `solver` in tolerance mode, at most `iterations`."""
    sim = _scene(resolution)
    try:
        for step in range(WARMUP_STEPS):
            _probe_at(sim, step)
            sim.step(DT_S)
        _probe_at(sim, WARMUP_STEPS)
        sim.pressure_solver = solver
        sim.pressure_tolerance = TOLERANCE
        sim.pressure_iterations = iterations
        return sim.step(DT_S)
    finally:
        sim.close()


def _measure(resolution: Sequence[int], solver: str) -> Dict[str, object]:
    cap = MULTIGRID_MAX_ITERATIONS if solver == "multigrid" else JACOBI_SWEEPS[tuple(resolution)]
    report = _solve(resolution, solver, cap)
    iterations = report.pressure_iterations
    pressure_ms = float(report.gpu_ms.get("pressure", float("nan")))
    initial, reached = report.initial_relative_residual, report.relative_residual
    factor = (reached / initial) ** (1.0 / iterations) if iterations > 0 and initial > 0 and reached > 0 else None
    per_iteration = pressure_ms / iterations if iterations else None
    how, to_tolerance = "measured", pressure_ms
    if reached > TOLERANCE and solver == "jacobi" and per_iteration:
        half = _solve(resolution, solver, iterations // 2)
        rate = (reached / half.relative_residual) ** (1.0 / (iterations - half.pressure_iterations))
        if rate < 1.0:
            more = math.log(TOLERANCE / reached) / math.log(rate)
            how, to_tolerance = f"extrapolated (rate {rate:.6f}/sweep)", (iterations + more) * per_iteration
        else:
            how, to_tolerance = "not reached (no progress)", None
    elif reached > TOLERANCE:
        how, to_tolerance = "not reached", None
    return {
        "grid": "x".join(str(n) for n in resolution),
        "solver": solver,
        "iterations": iterations,
        "pressure_ms": round(pressure_ms, 1),
        "ms_per_iteration": round(per_iteration, 3) if per_iteration else None,
        "initial_residual": float(f"{initial:.3e}"),
        "reached_residual": float(f"{reached:.3e}"),
        "convergence_factor": round(factor, 5) if factor is not None else None,
        "time_to_tolerance_ms": round(to_tolerance, 1) if to_tolerance is not None else None,
        "how": how,
    }


def run(quick: bool = False) -> dict:
    grids = QUICK_GRIDS if quick else FULL_GRIDS
    rows: List[List[object]] = []
    by_grid: Dict[str, Dict[str, Dict[str, object]]] = {}
    for resolution in grids:
        for solver in ("jacobi", "multigrid"):
            report.progress(f"pressure: {'x'.join(map(str, resolution))} {solver}")
            m = _measure(resolution, solver)
            rows.append([m[c] for c in COLUMNS])
            by_grid.setdefault(str(m["grid"]), {})[solver] = m
    notes = [f"time to a relative residual of {TOLERANCE:g}, warm-started, tolerance mode; "
             "pressure_ms is the GPU timer of the whole pressure stage",
             "an iteration is one Jacobi sweep (with a residual check every 16) or one CG iteration "
             "(one V-cycle, a matrix product, two dot products and the residual read-back)",
             "device: " + str(hf.probe_device("").get("renderer", "?")),
             "CPU load average (1 min) at the end: %.1f on %d cores" % (os.getloadavg()[0], os.cpu_count() or 0)]
    for grid, solvers in by_grid.items():
        j, m = solvers["jacobi"], solvers["multigrid"]
        if j["time_to_tolerance_ms"] and m["time_to_tolerance_ms"]:
            bound = "" if j["how"] == "measured" else "at least "
            notes.append(f"{grid}: multigrid reaches {TOLERANCE:g} {bound}"
                         f"{j['time_to_tolerance_ms'] / m['time_to_tolerance_ms']:.0f}x faster than Jacobi")
    return {"title": "Pressure solve: Jacobi vs multigrid-preconditioned CG", "columns": COLUMNS, "rows": rows,
            "notes": notes}


def main(argv: Sequence[str] | None = None) -> int:
    return report.section_main("pressure", run, argv)


if __name__ == "__main__":
    sys.exit(main())
