# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``mantaflow`` section's second comparison: the bake as a user runs it.

``python3 -m hapticfluid bake SCENE.json`` (a fresh process: interpreter start, module import,
shader compilation, the trajectory check, every step, the read-backs, the OpenVDB frame files
with density and velocity in half floats, the checkpoints and the manifest) against Blender
3.4's Mantaflow baking the same scene (bench/mantaflow_scene.py), alternated in rounds.

The scene is the seed paper's grid: 100 x 100 x 70 cells in a closed 1 x 1 x 0.7 m box, a smoke
inflow sphere near the floor, a sphere moving across the plume at mid height (keyed on every
frame on both sides), ``FRAMES`` frames at ``FPS``, one step per frame; the engine's pressure
solve is multigrid-preconditioned CG to a relative residual of ``TOLERANCE`` every step (the
bake's manifest records the worst residual each session reached, checked here).

Before/after: with ``HAPTICFLUID_BENCH_BASELINE`` set to a folder holding another build of the
``hapticfluid`` package (e.g. one made from an earlier commit), every round also runs that
build's bake command, right after this one's, as a third row ("baseline"): a change's effect
measured side by side on a machine whose speed drifts.

Run alone: ``python3 -m hapticfluid.bench.mantaflow_bake [--quick] [--json PATH]``.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, List, Optional

import hapticfluid as hf
from hapticfluid.bake import cache as _cache
from hapticfluid.bench import mantaflow_loop as mantaflow, report
from hapticfluid.bench.scene import SEED_DOMAIN, BenchScene

FPS = 24
FULL = {"resolution_max": 100, "frames": 20, "rounds": 3}
QUICK = {"resolution_max": 20, "frames": 3, "rounds": 2}
TOLERANCE = 1e-3  # relative residual of every step's pressure solve
MAX_ITERATIONS = 50  # CG iterations per solve at most (the solve stops at TOLERANCE first)
GRIDS = ("density", "velocity")
BAKE_TIMEOUT_S = 1800
BASELINE_ENV = "HAPTICFLUID_BENCH_BASELINE"  # folder whose hapticfluid package is the baseline build


def bench_scene(resolution_max: int) -> BenchScene:
    """The benchmark scene on Mantaflow's grid (cubic cells: the longest edge over resolution_max)."""
    h = max(SEED_DOMAIN) / resolution_max
    resolution = tuple(max(1, round(l / h)) for l in SEED_DOMAIN)
    domain = tuple(n * h for n in resolution)
    return BenchScene(resolution, domain, dt_s=1.0 / FPS)  # type: ignore[arg-type]


def bake_scene_dict(scene: BenchScene, frames: int, cache_dir: Path) -> Dict[str, object]:
    """The scene file the bake command reads: the benchmark scene, closed box, converged solver."""
    p = scene.physics
    keys = [{"frame": f, "location": list(scene.probe_pose(f / FPS)[0])} for f in range(0, frames + 1)]
    return {
        "domain": {"origin": [0.0, 0.0, 0.0], "size": list(scene.domain_size)},
        "resolution": max(scene.resolution),
        "fluid": {"fluid_density": p.fluid_density, "open_top": False, "vorticity": p.vorticity,
                  "heat_buoyancy": p.heat_buoyancy, "smoke_weight": p.smoke_weight,
                  "smoke_dissipation": p.smoke_dissipation, "heat_dissipation": p.heat_dissipation,
                  "pressure_solver": "multigrid", "pressure_iterations": MAX_ITERATIONS,
                  "pressure_tolerance": TOLERANCE},
        "source": {"centre": list(scene.source_centre_m), "radius": scene.source_radius_m,
                   "density": p.source_density, "temperature": p.source_temperature},
        "probe": {"shape": "sphere", "radius": scene.probe_radius_m, "keys": keys},
        "frames": {"start": 1, "end": frames, "fps": FPS},
        "substeps": 1,
        "cache": {"directory": str(cache_dir), "grids": list(GRIDS), "compression": "blosc",
                  "half_float": True, "tolerance": 1e-3},
    }


def _file_gaps_ms(paths: List[Path]) -> List[float]:
    times = sorted(p.stat().st_mtime for p in paths)
    return [(b - a) * 1000.0 for a, b in zip(times, times[1:])]


def run_bake_command(scene: BenchScene, frames: int, workdir: Path,
                     package_dir: Optional[str] = None, backend: Optional[str] = None) -> Dict[str, object]:
    """``python3 -m hapticfluid bake`` on the scene in a child process (the package on this
    interpreter's path, or the one in ``package_dir``; ``--backend`` when given): wall and CPU
    seconds of the whole command, the gaps between its frame files, and the manifest's solver
    figures."""
    cache = workdir / "cache"
    scene_path = workdir / "scene.json"
    scene_path.write_text(json.dumps(bake_scene_dict(scene, frames, cache)), encoding="utf-8")
    cmd = [sys.executable, "-m", "hapticfluid", "bake", str(scene_path), "--quiet"]
    if backend:
        cmd += ["--backend", backend]
    env = dict(os.environ)
    if package_dir:
        env["PYTHONPATH"] = os.pathsep.join([package_dir, env.get("PYTHONPATH", "")])
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=BAKE_TIMEOUT_S, env=env)
    except subprocess.TimeoutExpired:
        raise hf.HapticFluidError(f"the bake command took longer than {BAKE_TIMEOUT_S} s") from None
    total_s = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        tail = (proc.stdout + proc.stderr).strip().splitlines()[-15:]
        raise hf.HapticFluidError(f"the bake command failed (exit {proc.returncode}):\n" + "\n".join(tail))
    files = [_cache.frame_path(cache, f) for f in _cache.list_frames(cache)]
    if len(files) != frames:
        raise hf.HapticFluidError(f"the bake command wrote {len(files)} frame files, expected {frames}")
    manifest = _cache.read_manifest(cache) or {}
    session = (manifest.get("sessions") or [{}])[-1]
    pressure = session.get("pressure") or {}
    worst = pressure.get("max_relative_residual")
    if worst is None or pressure.get("unconverged_steps", 1) != 0:
        raise hf.HapticFluidError(f"the bake's pressure solves did not all reach {TOLERANCE:g} "
                                  f"(manifest: {pressure})")
    return {"total_s": total_s,
            "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
            "gaps_ms": _file_gaps_ms(files), "bytes": sum(p.stat().st_size for p in files),
            "max_relative_residual": float(worst), "max_iterations": int(pressure.get("max_iterations", 0)),
            "mean_iterations": float(pressure.get("mean_iterations", 0.0))}


def _rows(round_label, scene: BenchScene, frames: int, manta: Dict[str, object],
          runs: Dict[str, Dict[str, object]]) -> List[list]:
    manta_ms = manta["bake_s"] * 1000.0 / frames
    times = [t for _, t in manta["frame_files"]]
    gaps = [(b - a) * 1000.0 for a, b in zip(times, times[1:])]
    manta_steady = report.median(gaps) if gaps else None
    manta_cpu = manta["bake_cpu_s"] * 1000.0 / frames
    rows = [[round_label, f"Mantaflow (Blender {manta['blender_version']})", scene.label, frames, 1,
             manta["bake_s"], manta_ms, manta_steady, manta_cpu, 1.0, 1.0 if manta_steady else None, 1.0]]
    for label, ours in runs.items():
        ours_ms = ours["total_s"] * 1000.0 / frames
        ours_steady = report.median(ours["gaps_ms"]) if ours["gaps_ms"] else None
        ours_cpu = ours["cpu_s"] * 1000.0 / frames
        steady_ratio = manta_steady / ours_steady if manta_steady and ours_steady else None
        rows.append([round_label, label, scene.label, frames, 1, ours["total_s"], ours_ms, ours_steady, ours_cpu,
                     manta_ms / ours_ms, steady_ratio, manta_cpu / ours_cpu])
    return rows


def run(quick: bool = False, log=report.progress) -> dict:
    cfg = QUICK if quick else FULL
    res_max, frames, n_rounds = cfg["resolution_max"], cfg["frames"], cfg["rounds"]
    scene = bench_scene(res_max)
    baseline = os.environ.get(BASELINE_ENV) or None
    # This build on each backend (the CPU backend first: it is auto's choice without a GPU), and
    # the baseline build as it chooses.
    builds = {f"hapticfluid bake, CPU backend (multigrid to {TOLERANCE:g})": (None, "cpu"),
              f"hapticfluid bake, GPU backend: {hf.probe_device(backend='gpu')['renderer']}": (None, "gpu")}
    if baseline:
        builds[f"baseline: {baseline}"] = (baseline, None)
    rounds: List[List[list]] = []
    residuals: List[float] = []
    iterations: List[float] = []
    manta: Dict[str, object] = {}
    for r in range(1, n_rounds + 1):
        with tempfile.TemporaryDirectory(prefix="hf-bench-mantaflow-bake-") as tmp:
            if log:
                log(f"mantaflow (bake command): round {r}/{n_rounds}: Mantaflow bakes {scene.label}, closed box, "
                    f"{frames} frames ...")
            manta = mantaflow.run_mantaflow(scene, res_max, frames, Path(tmp), fps=FPS, open_top=False)
        if manta["grid"] is not None and tuple(manta["grid"]) != scene.resolution:
            raise hf.HapticFluidError(f"Mantaflow's grid is {manta['grid']}, expected {scene.resolution}")
        runs: Dict[str, Dict[str, object]] = {}
        order = list(builds.items())
        if r % 2 == 0:
            order.reverse()  # this build and the baseline take turns going first
        for label, (package, backend) in order:
            with tempfile.TemporaryDirectory(prefix="hf-bench-bake-command-") as tmp:
                if log:
                    log(f"mantaflow (bake command): round {r}/{n_rounds}: python3 -m hapticfluid bake "
                        f"({'this build' if package is None else package}, backend {backend or 'auto'}) ...")
                runs[label] = run_bake_command(scene, frames, Path(tmp), package, backend)
        runs = {label: runs[label] for label in builds}  # rows in a fixed order
        ours = runs[next(iter(builds))]
        residuals.append(ours["max_relative_residual"])
        iterations.append(ours["mean_iterations"])
        rounds.append(_rows(r, scene, frames, manta, runs))
    rows = [row for round_rows in rounds for row in round_rows] + mantaflow.median_rows(rounds)
    notes = [
        f"the bake as a user runs it: `python3 -m hapticfluid bake scene.json` in a new process (start-up, "
        f"shader compilation, trajectory check, {frames} steps, read-backs, OpenVDB files with "
        f"{' + '.join(GRIDS)} as half floats (blosc), checkpoint and manifest per frame) against "
        f"Blender {manta.get('blender_version', '?')}'s Mantaflow `bake_all` on the same scene",
        f"scene: {scene.label} cells of {scene.cell_size * 100:g} cm, closed box, {frames} frames at {FPS} fps, "
        f"one step per frame (Mantaflow: adaptive time stepping off), smoke inflow sphere "
        f"r={scene.source_radius_m:.3g} m, a sphere r={scene.probe_radius_m:.3g} m moving along x, keyed on "
        "every frame",
        f"hapticfluid's pressure: multigrid CG to a relative residual of {TOLERANCE:g} every step (at most "
        f"{MAX_ITERATIONS} iterations); worst residual per round {', '.join(f'{x:.2g}' for x in residuals)}, "
        f"mean CG iterations per step {', '.join(f'{x:.1f}' for x in iterations)}; Mantaflow's is PCG to its "
        "own tolerance",
        "total s: the whole command (hapticfluid: the child process from start to exit; Mantaflow: the "
        "bake operator inside Blender, Blender's own start-up not counted); steady ms/frame: median gap "
        "between consecutive frame files' modification times; CPU: all threads (hapticfluid: the child "
        "process's rusage; Mantaflow: process time around the bake)",
        f"{n_rounds} rounds, each Mantaflow then hapticfluid on the CPU and the GPU backend (taking turns going "
        f"first)" + (f" and the baseline build in {baseline}" if baseline else "") + "; 'median' rows: the median over the rounds of "
        "each figure, ratios included (the median of the per-round ratios)",
    ]
    return {"title": "Mantaflow (Blender) against the bake command, same scene and machine",
            "columns": mantaflow.COLUMNS, "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("mantaflow_bake", run))
