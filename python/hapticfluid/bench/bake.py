# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake benchmark: seconds per frame and bytes per frame file at several resolutions, with and
without half floats, for the demo bake scene (examples/bake_demo.json's plume + sweeping probe,
built here so the benchmark does not depend on the source tree).

    python3 -m hapticfluid.bench.bake [--quick] [--json PATH]   (the JSON is written atomically)
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import List

from hapticfluid.bake import bake, list_frames, scene_from_dict
from hapticfluid.bake.cache import frame_path
from hapticfluid.bench import report


def _scene(cache: Path, resolution: int, frames: int, half: bool, grids) -> dict:
    return {
        "domain": {"origin": [0, 0, 0], "size": [1, 1, 1]},
        "resolution": resolution,
        "fluid": {"open_top": True, "vorticity": 0.4, "heat_buoyancy": 1.0, "smoke_dissipation": 0.05,
                  "heat_dissipation": 0.4, "pressure_iterations": 40},
        "source": {"centre": [0.5, 0.5, 0.1], "radius": 0.07, "temperature": 8.0},
        "probe": {"shape": "sphere", "radius": 0.08,
                  "keys": [{"frame": 0, "location": [0.25, 0.5, 0.55]},
                           {"frame": frames, "location": [0.75, 0.5, 0.55]}]},
        "frames": {"start": 1, "end": frames, "fps": 24},
        "substeps": 2,
        "cache": {"directory": str(cache), "grids": list(grids), "compression": "blosc", "half_float": half,
                  "tolerance": 1e-3},
    }


def run(quick: bool = False) -> dict:
    sizes = (16, 24) if quick else (32, 64, 96)
    frames = 4 if quick else 12
    rows = []
    with tempfile.TemporaryDirectory(prefix="hf_bench_bake_") as tmp:
        for n in sizes:
            for grids in (("density",), ("density", "velocity", "pressure")):
                for half in (False, True):
                    cache = Path(tmp) / f"c{n}{len(grids)}{int(half)}"
                    scene = scene_from_dict(_scene(cache, n, frames, half, grids))
                    finished: List[float] = []  # bake wall time when each frame was complete, s

                    def on_progress(p, finished=finished):
                        if p.frame_finished:
                            finished.append(p.elapsed_s)

                    result = bake(scene, progress=on_progress)
                    sizes_b = [frame_path(cache, f).stat().st_size for f in list_frames(cache)]
                    # Steady cost per frame from frame 1's end to the last's, so the one-off
                    # simulation creation (shader compilation) and trajectory check stay out of it.
                    steady = (finished[-1] - finished[0]) / (len(finished) - 1)
                    rows.append([f"{n}^3", "+".join(grids), "half" if half else "float", frames,
                                 round(steady, 4), round(sizes_b[-1] / 1024, 1),
                                 round(sum(sizes_b) / len(sizes_b) / 1024, 1), round(finished[0], 3),
                                 result.status])
    return {
        "title": "Bake: demo plume + sweeping probe, 2 substeps/frame, blosc, tolerance 1e-3",
        "columns": ["resolution", "grids", "precision", "frames", "s/frame", "last frame KiB",
                    "mean KiB/frame", "first frame s", "status"],
        "rows": rows,
        "notes": ["s/frame: mean wall time per frame after the first (steps, read-backs, VDB write, "
                  "checkpoint and manifest)",
                  "first frame s: from the start of bake() to frame 1 complete: simulation creation "
                  "(shader compilation), the trajectory check and frame 1",
                  "the smoke grows over the frames, so later files are larger than the mean",
                  "timings depend on the machine's load; take them as indications"],
    }


if __name__ == "__main__":
    raise SystemExit(report.section_main("bake", run))
