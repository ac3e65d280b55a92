# SPDX-License-Identifier: GPL-3.0-or-later
"""Why the pressure solve's warm start helps or not (issue 20): a measurement helper, not a section.

For a scene (the bake scene: the seed's box closed, 24 fps, one step per frame; or the haptic
scene: the benchmark scene at 48^3, open top, 30 steps/s) it runs ``steps`` steps with the
multigrid solve in tolerance mode and reports per step:

- the solve's starting relative residual (``StepReport.initial_relative_residual``: what the
  solve started from after its predictor) and the CG iterations it took;
- how the solved (dynamic) pressure of step n relates to step n-1's: correlation, norm ratio
  and the least-squares scale <p_n, p_n-1> / <p_n-1, p_n-1>;
- at every ``split_every``-th step, what the step's right-hand side is made of: the step is
  re-run from the same state with one term switched off at a time (buoyancy, vorticity
  confinement, the probe's velocity, the probe), each solved tightly from p = 0; the pressure
  is linear in the right-hand side, so p_full - p_without is that term's part (its share =
  its norm over the full pressure's, and its correlation with the previous step's pressure).

Run: ``python3 -m hapticfluid.bench.warm_start --scene bake --resolution-max 50 --steps 12``.
Prints one JSON document (``--json PATH`` also writes it).
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Dict, List, Optional

import numpy as np

import hapticfluid as hf
from hapticfluid.bench import mantaflow_bake
from hapticfluid.bench.scene import BenchScene

TOLERANCE = 1e-3
SPLIT_TOLERANCE = 1e-5
MAX_ITERATIONS = 60


def _scene(name: str, resolution_max: int) -> tuple:
    if name == "bake":
        return mantaflow_bake.bench_scene(resolution_max), False
    n = resolution_max
    return BenchScene((n, n, n), (1.0, 1.0, 1.0)), True


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    a = a - a.mean()
    b = b - b.mean()
    d = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / d) if d > 0 else 0.0


def _norm(a: np.ndarray) -> float:
    return float(np.sqrt((a.astype(np.float64) ** 2).sum()))


def _laplacian(p: np.ndarray, fluid: np.ndarray, open_top: bool) -> np.ndarray:
    """A p on the CPU (sum over fluid neighbours of p - p_nb, walls and solids Neumann, the open
    top a 0 Pa ghost), binary faces: an estimate of the engine's operator (cut faces weigh 1)."""
    q = np.where(fluid, p, 0.0)
    out = np.zeros_like(q)
    for axis in range(3):
        for shift in (1, -1):
            nb = np.roll(q, shift, axis=axis)
            nbf = np.roll(fluid, shift, axis=axis)
            edge = [slice(None)] * 3
            edge[axis] = 0 if shift == 1 else -1
            nbf[tuple(edge)] = False
            out += np.where(nbf, q - nb, 0.0)
    if open_top:
        out[:, :, -1] += q[:, :, -1]
    return np.where(fluid, out, 0.0)


def _predictors(cur: np.ndarray, prev: np.ndarray, prev2: Optional[np.ndarray], fluid: np.ndarray,
                open_top: bool) -> Dict[str, float]:
    """Starting relative residual ||b - A x0|| / ||b|| of candidate starts x0, with b = A p_n (the
    solved pressure; exact to the solve's tolerance) and the CPU operator: the plain warm start,
    the min-residual scaled one, the linear extrapolation 2 p_n-1 - p_n-2 and the min-residual
    combination of p_n-1 and p_n-2."""
    a = lambda x: _laplacian(x, fluid, open_top)  # noqa: E731
    b = a(cur)
    bb = float((b * b).sum())
    if bb <= 0:
        return {}
    rel = lambda x0: float(np.sqrt(((b - a(x0)) ** 2).sum() / bb))  # noqa: E731
    ap1 = a(prev)
    out = {"warm": rel(prev), "zero": 1.0}
    d = float((ap1 * ap1).sum())
    out["scaled"] = rel(prev * (float((b * ap1).sum()) / d)) if d > 0 else 1.0
    if prev2 is not None:
        out["extrapolated"] = rel(2.0 * prev - prev2)
        ap2 = a(prev2)
        m = np.array([[d, float((ap1 * ap2).sum())], [float((ap1 * ap2).sum()), float((ap2 * ap2).sum())]])
        v = np.array([float((b * ap1).sum()), float((b * ap2).sum())])
        try:
            c = np.linalg.solve(m, v)
            out["span2"] = rel(c[0] * prev + c[1] * prev2)
        except np.linalg.LinAlgError:
            pass
    return out


def _near_probe(sim: hf.Simulation, centre, radius: float, cells: float) -> np.ndarray:
    nx, ny, nz = sim.resolution
    h = sim.cell_size
    x, y, z = np.meshgrid(*[(np.arange(n) + 0.5) * h for n in (nx, ny, nz)], indexing="ij")
    d = np.sqrt((x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2)
    return np.abs(d - radius) <= cells * h


def _split(sim: hf.Simulation, scene: BenchScene, before: dict, probe_t: float) -> Dict[str, np.ndarray]:
    """The step from `before` re-run with each term off, solved tightly from p = 0."""
    tol, its = sim.pressure_tolerance, sim.pressure_iterations
    saved = {k: getattr(sim, k) for k in ("heat_buoyancy", "smoke_weight", "vorticity")}
    out: Dict[str, np.ndarray] = {}
    cold = dict(before)
    cold["pressure"] = np.zeros_like(before["pressure"])
    variants = {"full": {}, "no_buoyancy": {"heat_buoyancy": 0.0, "smoke_weight": 0.0},
                "no_vorticity": {"vorticity": 0.0}, "probe_still": "still", "no_probe": "none"}
    try:
        sim.pressure_tolerance, sim.pressure_iterations = SPLIT_TOLERANCE, 200
        for name, change in variants.items():
            sim.set_state(cold)
            if isinstance(change, dict):
                for k, v in change.items():
                    setattr(sim, k, v)
            centre, velocity = scene.probe_pose(probe_t)
            if change == "none":
                sim.clear_probe()
            else:
                sim.set_probe(centre, scene.probe_radius_m, velocity=(0.0, 0.0, 0.0) if change == "still" else velocity)
            sim.step(scene.dt_s)
            out[name] = sim.state()["pressure"].astype(np.float64)
            for k, v in saved.items():
                setattr(sim, k, v)
    finally:
        sim.pressure_tolerance, sim.pressure_iterations = tol, its
        sim.set_state(before)
        centre, velocity = scene.probe_pose(probe_t)
        sim.set_probe(centre, scene.probe_radius_m, velocity=velocity)
    return out


def measure(scene_name: str, resolution_max: int, steps: int, split_every: int, cut_cells: bool = True) -> dict:
    scene, open_top = _scene(scene_name, resolution_max)
    kwargs = scene.simulation_kwargs()
    kwargs["open_top"] = open_top
    sim = hf.Simulation(**kwargs, pressure_solver="multigrid", pressure_tolerance=TOLERANCE,
                        pressure_iterations=MAX_ITERATIONS)
    sim.cut_cells = cut_cells
    p = scene.physics
    sim.set_smoke_source(scene.source_centre_m, scene.source_radius_m, density=p.source_density,
                         temperature=p.source_temperature)
    scene.place_probe(sim, 0.0)
    rows: List[dict] = []
    prev: Optional[np.ndarray] = None
    prev2: Optional[np.ndarray] = None
    try:
        for n in range(steps):
            t_end = sim.time + scene.dt_s
            split = None
            if split_every and n > 0 and n % split_every == 0:
                parts = _split(sim, scene, sim.state(), t_end)
                full = parts["full"]
                nf = _norm(full)
                split = {"full_norm_pa": nf}
                for name in ("no_buoyancy", "no_vorticity", "probe_still", "no_probe"):
                    part = full - parts[name]
                    split[name.replace("no_", "").replace("probe_still", "probe_velocity") + "_share"] = \
                        _norm(part) / nf if nf else 0.0
                    if prev is not None:
                        split[name.replace("no_", "").replace("probe_still", "probe_velocity") + "_corr_prev"] = \
                            _corr(part, prev)
            scene.place_probe(sim, t_end)
            r = sim.step(scene.dt_s)
            cur = sim.state()["pressure"].astype(np.float64)
            row = {"step": n + 1, "initial_residual": r.initial_relative_residual, "iterations": r.pressure_iterations,
                   "reached": r.relative_residual, "pressure_ms": r.gpu_ms.get("pressure"), "p_norm_pa": _norm(cur)}
            if prev is not None:
                # The warm start's residual b - A p_prev = A (p_n - p_prev) (p_n solves A p = b to
                # 1e-3): where it lies. The CPU operator has binary faces: exact with --binary-faces.
                fluid = sim.cell_classes() < hf.CELL_BOUNDARY
                res = _laplacian(cur - prev, fluid, open_top)
                near = _near_probe(sim, scene.probe_pose(t_end)[0], scene.probe_radius_m, 2.0)
                r2 = float((res * res).sum())
                row["warm_residual_near_probe_share"] = float((res[near] ** 2).sum()) / r2 if r2 > 0 else 0.0
                row["near_probe_cells_share"] = float(near.sum()) / near.size
                row["cpu_predictors"] = _predictors(cur, prev, prev2, fluid, open_top)
                pp = float((prev * prev).sum())
                row.update({"corr_prev": _corr(cur, prev), "norm_ratio": _norm(cur) / max(_norm(prev), 1e-30),
                            "ls_scale": float((cur * prev).sum()) / pp if pp > 0 else 0.0,
                            "ls_rel_error": _norm(cur - (float((cur * prev).sum()) / pp if pp else 0.0) * prev)
                            / max(_norm(cur), 1e-30)})
            if split:
                row["split"] = split
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
            prev2, prev = prev, cur
    finally:
        sim.close()
    return {"scene": scene_name, "resolution": list(scene.resolution), "dt_s": scene.dt_s, "open_top": open_top,
            "cut_cells": cut_cells,
            "tolerance": TOLERANCE, "rows": rows}


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", choices=("bake", "haptic"), default="bake")
    ap.add_argument("--resolution-max", type=int, default=50)
    ap.add_argument("--steps", type=int, default=12)
    ap.add_argument("--split-every", type=int, default=4, help="0: no right-hand-side split")
    ap.add_argument("--binary-faces", action="store_true",
                    help="cut_cells off: the CPU operator of the residual's location is then exact")
    ap.add_argument("--json", default="")
    a = ap.parse_args(argv)
    doc = measure(a.scene, a.resolution_max, a.steps, a.split_every, not a.binary_faces)
    text = json.dumps(doc, indent=1)
    if a.json:
        with open(a.json, "w", encoding="utf-8") as fh:
            fh.write(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
