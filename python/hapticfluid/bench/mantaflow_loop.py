# SPDX-License-Identifier: GPL-3.0-or-later
"""The ``mantaflow`` section's first comparison: Blender's built-in Mantaflow smoke against this
engine's step loop on the same scene, machine and run, and what both comparisons share (running
Mantaflow in Blender, the columns, the median of the rounds).

The scene is the seed paper's grid: a 1 x 1 x 0.7 m box of 100 x 100 x 70 cells (Mantaflow gas
domain with resolution_max 100), a smoke inflow sphere near the floor, a sphere moving along x
through the plume at mid height (a Mantaflow collision effector keyframed on every frame; the
engine's probe), vorticity confinement, open top, ``FRAMES`` frames at ``FPS``.

Mantaflow runs in ``blender --background --factory-startup`` (bench/mantaflow_scene.py): fixed
time steps (adaptive time stepping off, so Blender's dt is the frame length: one solver step
per frame), OpenVDB cache in a temporary folder, no noise; baked with ``bpy.ops.fluid.bake_all``.
Its ms per frame = bake wall time / frames (the approach of the baseline in
reference/measurements.md); its steady ms per frame = median gap between consecutive cache
files' modification times (frames 2..N).

The engine then runs the same frames: per frame, the same number of steps (one) of dt = 1/FPS
and a ``density()`` read-back (what a viewport or bake needs each frame). Its ms per frame =
(Simulation creation, shader compilation included, + all frames) / frames; steady = median
frame time of frames 2..N. The ratio is Mantaflow's ms per frame over ours. Both run in
``rounds`` rounds (Mantaflow, then the engine), each round's ratios side by side, and the
median of the rounds last.

The section (:mod:`hapticfluid.bench.mantaflow`) adds a second comparison
(:mod:`hapticfluid.bench.mantaflow_bake`), which uses run_mantaflow, COLUMNS and median_rows
from here.

Run alone: ``python3 -m hapticfluid.bench.mantaflow_loop [--quick] [--json PATH]``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import hapticfluid as hf
from hapticfluid.bench import engine, report
from hapticfluid.bench.scene import SEED_DOMAIN, BenchScene
from hapticfluid.bake.openvdb_python import import_openvdb

FPS = 30
# Rounds: Mantaflow then the engine, repeated; these shared machines run slower and faster by
# tens of percent over minutes, so each round's ratio is taken side by side and the median of
# the rounds is reported with them.
FULL = {"resolution_max": 100, "frames": 20, "rounds": 3}
QUICK = {"resolution_max": 20, "frames": 3, "rounds": 2}
STEPS_PER_FRAME = 1  # Mantaflow's, with adaptive time stepping off (dt = frame length)
BLENDER_TIMEOUT_S = 1800

SCENE_SCRIPT = Path(__file__).with_name("mantaflow_scene.py")
# Mantaflow registers its Python module with PyImport_AppendInittab when a bake starts; Python
# 3.12 and newer abort on that once the interpreter runs, so a Blender built against such a
# Python (Debian 13's Blender 4.3 on Python 3.13; blender.org embeds 3.11 up to 5.0) dies on
# every Mantaflow bake with this message. The section then fails saying so.
EMBEDDED_PYTHON_ABORT = "PyImport_AppendInittab() may not be called after Py_Initialize()"
COLUMNS = ["round", "solver", "grid", "frames", "steps/frame", "total s", "ms/frame", "steady ms/frame",
           "CPU ms/frame", "Mantaflow/this", "Mantaflow/this steady", "Mantaflow/this CPU"]


def find_blender() -> str:
    path = shutil.which("blender")
    if not path:
        raise hf.HapticFluidError("the mantaflow section needs Blender: no 'blender' on PATH "
                                  "(install Debian's blender package, or leave the section out "
                                  "with --sections)")
    return path


def blender_env(blender: str) -> Dict[str, str]:
    """The environment to run Blender in: its own folder first on PATH.

    Debian's Blender finds its Python's home through the first python3 on PATH; a pyenv
    interpreter folder in front (as pyenv's shims put it for the tools they run) would give it
    another standard library without Debian's dist-packages."""
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([os.path.dirname(blender), env.get("PATH", "")])
    return env


def _grid_resolution(vdb_path: Path) -> Optional[Tuple[int, int, int]]:
    """Mantaflow's grid from a cache file's metadata (None without OpenVDB's Python module)."""
    openvdb = import_openvdb()
    if openvdb is None:
        return None
    for grid in openvdb.readAllGridMetadata(str(vdb_path)):
        if grid.name == "density":
            return tuple(int(n) for n in grid.metadata["file_base_resolution"])  # type: ignore[return-value]
    return None


def run_mantaflow(scene: BenchScene, resolution_max: int, frames: int, workdir: Path, fps: int = FPS,
                  open_top: bool = True) -> Dict[str, object]:
    """Bake the scene in Blender (``fps`` frames per second, the box's top open or closed);
    returns bake seconds, per-frame file times and the grid."""
    blender = find_blender()
    cache = workdir / "cache"
    params = {
        "domain_size": list(scene.domain_size),
        "resolution_max": resolution_max,
        "frames": frames,
        "fps": fps,
        "open_top": open_top,
        "cache_dir": str(cache),
        "source_centre": list(scene.source_centre_m),
        "source_radius": scene.source_radius_m,
        "probe_radius": scene.probe_radius_m,
        "probe_path": [list(scene.probe_pose(f / fps)[0]) for f in range(1, frames + 1)],
        "vorticity": scene.physics.vorticity,
    }
    params_path = workdir / "params.json"
    result_path = workdir / "result.json"
    params_path.write_text(json.dumps(params), encoding="utf-8")
    cmd = [blender, "--background", "--factory-startup", "--python-exit-code", "1",
           "--python", str(SCENE_SCRIPT), "--", str(params_path), str(result_path)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=BLENDER_TIMEOUT_S,
                              cwd=workdir, env=blender_env(blender))
    except subprocess.TimeoutExpired:
        raise hf.HapticFluidError(f"Blender's Mantaflow bake took longer than {BLENDER_TIMEOUT_S} s") from None
    if EMBEDDED_PYTHON_ABORT in proc.stdout + proc.stderr:
        raise hf.HapticFluidError(f"this Blender's Mantaflow cannot bake: it aborts with '{EMBEDDED_PYTHON_ABORT}' "
                                  f"(Blender {blender} embeds Python 3.12+, where Mantaflow's start-up is fatal); "
                                  "use a Blender that embeds Python 3.11 (blender.org 4.2-5.0, Debian 12's 3.4) for "
                                  "this section, or leave it out with --sections")
    if proc.returncode != 0 or not result_path.is_file():
        tail = (proc.stdout + proc.stderr).strip().splitlines()[-15:]
        raise hf.HapticFluidError(f"Blender's Mantaflow bake failed (exit {proc.returncode}):\n"
                                  + "\n".join(tail))
    result = json.loads(result_path.read_text(encoding="utf-8"))
    files = result["frame_files"]
    if len(files) != frames:
        raise hf.HapticFluidError(f"Mantaflow wrote {len(files)} cache frames, expected {frames}")
    result["grid"] = _grid_resolution(cache / "data" / files[-1][0])
    return result


def run_engine(scene: BenchScene, frames: int, solver_kwargs: Dict[str, object]) -> Dict[str, object]:
    """The same frames on this engine (one pressure solver): steps + density() read-back per frame."""
    dt = 1.0 / FPS / STEPS_PER_FRAME
    t0 = time.perf_counter()
    cpu0 = time.process_time()  # all threads of this process, llvmpipe's included
    frame_ms: List[float] = []
    # The residual is a diagnostic (a production bake does not measure it): off, as Mantaflow
    # computes none beyond its own solver's stopping test. The engine section reports it.
    with scene.make_simulation(compute_residual=False, **solver_kwargs) as sim:
        setup_s = time.perf_counter() - t0
        for _ in range(frames):
            f0 = time.perf_counter()
            for _ in range(STEPS_PER_FRAME):
                scene.step(sim, dt)
            density = sim.density()
            frame_ms.append((time.perf_counter() - f0) * 1000.0)
        smoke = float(density.sum()) * scene.cell_size ** 3
    return {"total_s": time.perf_counter() - t0, "cpu_s": time.process_time() - cpu0, "setup_s": setup_s,
            "frame_ms": frame_ms, "smoke_m3": smoke}


def _round_rows(round_label, scene: BenchScene, frames: int, manta: Dict[str, object],
                ours: Dict[str, Dict[str, object]]) -> List[list]:
    """One round's rows: Mantaflow's, then one per engine solver with the ratios to it."""
    times = [t for _, t in manta["frame_files"]]
    gaps_ms = [(b - a) * 1000.0 for a, b in zip(times, times[1:])]
    manta_ms = manta["bake_s"] * 1000.0 / frames
    manta_steady = report.median(gaps_ms) if gaps_ms else None
    manta_cpu = manta["bake_cpu_s"] * 1000.0 / frames
    label = scene.label
    rows = [[round_label, f"Mantaflow (Blender {manta['blender_version']})", label, frames, STEPS_PER_FRAME,
             manta["bake_s"], manta_ms, manta_steady, manta_cpu, 1.0, 1.0 if manta_steady else None, 1.0]]
    for solver, run_ in ours.items():
        ours_ms = run_["total_s"] * 1000.0 / frames
        ours_steady = report.median(run_["frame_ms"][1:]) if frames > 1 else None
        ours_cpu = run_["cpu_s"] * 1000.0 / frames
        steady_ratio = manta_steady / ours_steady if manta_steady and ours_steady else None
        rows.append([round_label, f"hapticfluid ({solver})", label, frames, STEPS_PER_FRAME, run_["total_s"],
                     ours_ms, ours_steady, ours_cpu, manta_ms / ours_ms, steady_ratio, manta_cpu / ours_cpu])
    return rows


def median_rows(rounds: List[List[list]]) -> List[list]:
    """Per contender, the median over the rounds of every figure (the ratios included: the
    median of the per-round ratios, not a ratio of medians)."""
    out = []
    for i, first in enumerate(rounds[0]):
        row = ["median", *first[1:5]]
        for col in range(5, len(first)):
            values = [r[i][col] for r in rounds if r[i][col] is not None]
            row.append(report.median(values) if values else None)
        out.append(row)
    return out


def run_step_loop(quick: bool = False, log=report.progress) -> dict:
    """The step-loop comparison alone (one step and a density() read-back per frame, no files)."""
    cfg = QUICK if quick else FULL
    res_max, frames, n_rounds = cfg["resolution_max"], cfg["frames"], cfg["rounds"]
    # Mantaflow's cells are cubic: the longest edge over resolution_max.
    h = max(SEED_DOMAIN) / res_max
    resolution = tuple(max(1, round(l / h)) for l in SEED_DOMAIN)
    domain = tuple(n * h for n in resolution)
    scene = BenchScene(resolution, domain, dt_s=1.0 / FPS)  # type: ignore[arg-type]
    rounds: List[List[list]] = []
    ours: Dict[str, Dict[str, object]] = {}
    manta: Dict[str, object] = {}
    for r in range(1, n_rounds + 1):
        with tempfile.TemporaryDirectory(prefix="hf-bench-mantaflow-") as tmp:
            if log:
                log(f"mantaflow: round {r}/{n_rounds}: baking {scene.label}, {frames} frames in Blender ...")
            manta = run_mantaflow(scene, res_max, frames, Path(tmp))
        if manta["grid"] is not None and tuple(manta["grid"]) != resolution:
            raise hf.HapticFluidError(f"Mantaflow's grid is {manta['grid']}, expected {resolution}")
        ours = {}
        for solver, kwargs in engine.SOLVERS:
            if log:
                log(f"mantaflow: round {r}/{n_rounds}: the engine ({solver}) on {scene.label}, {frames} frames ...")
            ours[solver] = run_engine(scene, frames, kwargs)
        rounds.append(_round_rows(r, scene, frames, manta, ours))
    rows = [row for round_rows in rounds for row in round_rows] + median_rows(rounds)
    label = scene.label
    setups = ", ".join(f"{solver} {r['setup_s'] * 1000:.0f} ms" for solver, r in ours.items())
    notes = [
        f"same scene, grid and frames: {label} cells of {h * 100:g} cm, {frames} frames at {FPS} fps, "
        f"smoke inflow sphere r={scene.source_radius_m:.3g} m, moving sphere r={scene.probe_radius_m:.3g} m "
        f"(x = {scene.domain_size[0] / 2:g} + {scene.sweep_amplitude * scene.domain_size[0]:g} "
        f"sin(2 pi t / {scene.sweep_period_s:g} s) m), vorticity, open top",
        "Mantaflow: adaptive time stepping off, so one step of dt = frame length per frame; its "
        "pressure solve is PCG to its default tolerance; its bake also writes an OpenVDB cache "
        "frame (density, flame, temperature, shadow, velocity)",
        f"hapticfluid: one step of 1/{FPS} s per frame per pressure solver of the engine section "
        f"(residual diagnostic off; the engine section reports the residual each reaches) plus a "
        f"density() read-back; no file writes; creation (shader compilation: {setups}) is in the total",
        "ms/frame = total wall time / frames (setup included); steady = median of frames 2..N "
        "(Mantaflow: gaps between its cache files' modification times); CPU ms/frame = process CPU "
        "time of all threads / frames (Mantaflow: of the bake call in Blender), the figure least "
        "disturbed by other load on the machine",
        f"{n_rounds} rounds, each Mantaflow then the engine; 'median' rows: the median over the "
        "rounds of each figure, ratios included (the median of the per-round ratios)",
    ]
    if manta["grid"] is None:
        notes.append("Mantaflow's grid was not checked against its cache (no OpenVDB Python module); "
                     f"computed from resolution_max {res_max}: {label}")
    else:
        notes.append(f"Mantaflow's grid, read from its cache's file_base_resolution: {label}")
    return {"title": "Mantaflow (Blender) against this engine, same scene and machine",
            "columns": COLUMNS, "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("mantaflow_loop", run_step_loop))
