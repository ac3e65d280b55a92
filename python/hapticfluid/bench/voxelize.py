# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``voxelize``: GPU time to voxelize a moving closed triangle mesh.

A UV sphere of 1k, 10k and 100k triangles (radius 0.3 m, in a 1 m box) is set as the mesh
probe; every step it is given a new pose (turned and shifted), and the step's GPU timer mark
``voxelize`` (transform + crossings + fill: the whole mesh -> solid mask and rigid velocity)
is recorded. The analytic sphere probe is timed the same way for comparison. The first step
after setting a mesh (upload, shader compilation) is not counted.

Run alone: ``python3 -m hapticfluid.bench.voxelize [--quick] [--json PATH]``.
"""

from __future__ import annotations

import math
import statistics
from typing import List, Sequence

import numpy as np

import hapticfluid as hf
from hapticfluid import meshes
from hapticfluid.bench import report

FULL_GRIDS = (64, 128)
QUICK_GRIDS = (64,)
SPHERES = ((25, 20), (100, 50), (250, 200))  # (slices, rings): 1k, 10k, 100k triangles
FULL_STEPS = 7
QUICK_STEPS = 3
RADIUS_M = 0.3
DT_S = 0.01

COLUMNS = ["grid", "probe", "triangles", "steps", "voxelize ms median", "voxelize ms min", "step wall ms median"]


def _pose(i: int) -> np.ndarray:
    """matrix_world of step i: a turn about a skew axis and a small shift (m)."""
    angle = 0.05 * i
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    k = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)
    m[:3, 3] = (0.5 + 0.01 * math.sin(i), 0.5, 0.5 + 0.01 * math.cos(i))
    return m


def _measure(sim: hf.Simulation, steps: int, set_pose) -> List[List[float]]:
    set_pose(0)
    sim.step(DT_S)  # upload and first use: not counted
    gpu, wall = [], []
    for i in range(1, steps + 1):
        set_pose(i)
        r = sim.step(DT_S)
        gpu.append(r.gpu_ms["voxelize"])
        wall.append(r.wall_ms)
    return [gpu, wall]


def run(quick: bool = False, grids: Sequence[int] = (), log=None) -> dict:
    grids = tuple(grids) or (QUICK_GRIDS if quick else FULL_GRIDS)
    steps = QUICK_STEPS if quick else FULL_STEPS
    rows = []
    renderer = ""
    for n in grids:
        with hf.Simulation(resolution=(n, n, n), pressure_iterations=1, compute_residual=False,
                           gravity=(0, 0, 0)) as sim:
            renderer = str(sim.device["renderer"])
            label = f"{n}^3"
            if log:
                log(f"voxelize: {label} sphere")
            sim.set_probe((0.5, 0.5, 0.5), RADIUS_M)
            gpu, wall = _measure(sim, steps, lambda i: sim.set_probe_pose(_pose(i), velocity=(0.1, 0, 0)))
            rows.append([label, "sphere (analytic)", 0, steps, statistics.median(gpu), min(gpu),
                         statistics.median(wall)])
            for slices, rings in SPHERES:
                vertices, triangles = meshes.uv_sphere(slices, rings, RADIUS_M)
                if log:
                    log(f"voxelize: {label} mesh {len(triangles)} triangles")
                sim.set_mesh_probe(vertices, triangles, _pose(0))
                gpu, wall = _measure(sim, steps, lambda i: sim.set_probe_pose(
                    _pose(i), velocity=(0.1, 0, 0), angular_velocity=(0, 0, 5.0)))
                rows.append([label, "mesh", int(len(triangles)), steps, statistics.median(gpu), min(gpu),
                             statistics.median(wall)])
    notes = [
        "voxelize ms: GPU timer of the step's 'voxelize' stage (for a mesh: vertex transform, "
        "per-triangle column crossings with atomics, per-column fill of solid mask and rigid velocity)",
        f"median and minimum over {steps} steps, a new pose every step; the first step after "
        "setting a probe (upload, shader compilation) is not counted",
        "step wall ms: the whole step with 1 pressure sweep, for scale",
        f"device: {renderer}; timings depend on the machine's load",
    ]
    return {"title": "Voxelization of a moving mesh probe", "columns": COLUMNS, "rows": rows, "notes": notes}


def write_json(result: dict, path: str) -> None:
    """The section alone as JSON, atomically (report.write_json_atomic: no NaN, umask permissions)."""
    report.write_json_atomic(path, result)


if __name__ == "__main__":
    # the same command line and JSON document (schema, machine, sections) as every other section
    raise SystemExit(report.section_main("voxelize", run))
