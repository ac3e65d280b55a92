# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section "force_roughness": how smooth the force on a moving probe is.

The scene of issue 18: a 1 m cube of water (no gravity), a sphere of radius 0.09 m moving at a
constant 0.25 m/s along +x through still fluid, the multigrid solver converged to a relative
residual of 1e-5 each step, dt = 1/120 s. After the start transient (the first
TRANSIENT_S seconds) the axial force should be steady; reported per grid are its mean, the
RMS of its step-to-step change and the largest single change, both divided by the mean
("roughness" and "largest jump"), and the cells the sphere's centre crossed in the window.
Each grid runs twice: with the probe's voxels (cut_cells off: whole cells switch in one step, so
the force jumps once per cell crossed) and with cut cells (Simulation.cut_cells, the default:
face fractions from the sphere smoothed into a one-cell radial ramp, so the discrete body, and
its added mass, no longer change with its position within a cell).

Run alone: ``python3 -m hapticfluid.bench.force_roughness [--quick] [--json PATH]``.
"""

from __future__ import annotations

import math
import sys
from typing import Dict, List, Sequence

import hapticfluid as hf
from hapticfluid.bench import report

RADIUS_M = 0.09
SPEED_M_S = 0.25
DT_S = 1.0 / 120.0
TOLERANCE = 1e-5
MAX_ITERATIONS = 100
TRANSIENT_S = 0.25
START_X_M = 0.30
FULL_GRIDS = (48, 96)
QUICK_GRIDS = (24,)
# Seconds of steady motion measured after the transient, per grid (96^3 crosses twice as many
# cells per second, so a shorter window holds as many jumps).
WINDOW_S = {24: 0.6, 48: 0.6, 96: 0.3}

COLUMNS = ["grid", "cut_cells", "steps", "cells_crossed", "mean_force_n", "roughness", "largest_jump", "mean_iterations",
           "max_residual"]


def force_series(n: int, window_s: float, cut_cells: bool) -> Dict[str, object]:
    """Axial forces (N) of the steps after the transient, with the solver's figures."""
    sim = hf.Simulation(resolution=(n, n, n), domain_size=(1.0, 1.0, 1.0), gravity=(0.0, 0.0, 0.0),
                        fluid_density=1000.0, pressure_solver="multigrid", pressure_tolerance=TOLERANCE,
                        pressure_iterations=MAX_ITERATIONS)
    sim.cut_cells = cut_cells
    transient = int(round(TRANSIENT_S / DT_S))
    steps = transient + int(round(window_s / DT_S))
    forces: List[float] = []
    iterations: List[int] = []
    residuals: List[float] = []
    try:
        for i in range(steps + 1):
            x = START_X_M + SPEED_M_S * DT_S * (i + 1)  # the pose at the step's end
            sim.set_probe((x, 0.5, 0.5), RADIUS_M, velocity=(SPEED_M_S, 0.0, 0.0))
            r = sim.step(DT_S)
            if i >= transient:
                forces.append(float(r.force[0]))
                iterations.append(int(r.pressure_iterations))
                residuals.append(float(r.relative_residual))
        h = sim.cell_size
    finally:
        sim.close()
    return {"forces": forces, "iterations": iterations, "residuals": residuals,
            "cells_crossed": SPEED_M_S * DT_S * (len(forces) - 1) / h}


def roughness(forces: Sequence[float]) -> Dict[str, float]:
    """Mean force, RMS of the step-to-step change / |mean|, largest change / |mean|."""
    mean = sum(forces) / len(forces)
    steps = [b - a for a, b in zip(forces, forces[1:])]
    rms = math.sqrt(sum(d * d for d in steps) / len(steps))
    largest = max(abs(d) for d in steps)
    return {"mean": mean, "roughness": rms / abs(mean), "largest_jump": largest / abs(mean)}


def _measure(n: int, cut_cells: bool) -> Dict[str, object]:
    s = force_series(n, WINDOW_S[n], cut_cells)
    r = roughness(s["forces"])
    return {
        "grid": f"{n}x{n}x{n}",
        "cut_cells": cut_cells,
        "steps": len(s["forces"]),
        "cells_crossed": round(float(s["cells_crossed"]), 2),
        "mean_force_n": round(r["mean"], 4),
        "roughness": round(r["roughness"], 4),
        "largest_jump": round(r["largest_jump"], 4),
        "mean_iterations": round(sum(s["iterations"]) / len(s["iterations"]), 1),
        "max_residual": float(f"{max(s['residuals']):.2e}"),
    }


def run(quick: bool = False) -> dict:
    rows: List[List[object]] = []
    for n in (QUICK_GRIDS if quick else FULL_GRIDS):
        for cut_cells in (False, True):
            report.progress(f"force_roughness: {n}^3, cut_cells {cut_cells}")
            m = _measure(n, cut_cells)
            rows.append([m[c] for c in COLUMNS])
    notes = [f"sphere r {RADIUS_M} m at {SPEED_M_S} m/s along x in a 1 m box of water, dt 1/120 s, multigrid "
             f"to {TOLERANCE:g}; the first {TRANSIENT_S} s left out",
             "roughness = RMS of the step-to-step change of the axial force / |mean|; largest_jump = largest "
             "change / |mean| (issue 18 goal: <= 0.05 and <= 0.15)"]
    return {"title": "Force roughness of a probe moving at constant speed", "columns": COLUMNS, "rows": rows,
            "notes": notes}


def main(argv: Sequence[str] | None = None) -> int:
    return report.section_main("force_roughness", run, argv)


if __name__ == "__main__":
    sys.exit(main())
