"""Bake benchmark: seconds per frame and bytes per frame file at several resolutions, with and
without half floats, for the demo bake scene (examples/bake_demo.json's plume + sweeping probe,
built here so the benchmark does not depend on the source tree).

    python3 -m hapticfluid.bench.bake [--quick] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

from hapticfluid.bake import bake, list_frames, scene_from_dict
from hapticfluid.bake.cache import frame_path


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
                    t0 = time.perf_counter()
                    result = bake(scene)
                    wall = time.perf_counter() - t0
                    sizes_b = [frame_path(cache, f).stat().st_size for f in list_frames(cache)]
                    rows.append([f"{n}^3", "+".join(grids), "half" if half else "float", frames,
                                 round(wall / frames, 3), round(sizes_b[-1] / 1024, 1),
                                 round(sum(sizes_b) / len(sizes_b) / 1024, 1), result.status])
    return {
        "title": "Bake: demo plume + sweeping probe, 2 substeps/frame, blosc, tolerance 1e-3",
        "columns": ["resolution", "grids", "precision", "frames", "s/frame", "last frame KiB",
                    "mean KiB/frame", "status"],
        "rows": rows,
        "notes": ["s/frame includes the steps, read-backs, VDB write, checkpoint and manifest",
                  "the smoke grows over the frames, so later files are larger than the mean",
                  "timings depend on the machine's load; take them as indications"],
    }


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python3 -m hapticfluid.bench.bake", description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="tiny grids, few frames (seconds)")
    p.add_argument("--json", metavar="PATH", help="also write the result as JSON")
    args = p.parse_args(argv)
    res = run(quick=args.quick)
    print(res["title"])
    widths = [max(len(str(c)), *(len(str(r[i])) for r in res["rows"])) for i, c in enumerate(res["columns"])]
    print("  ".join(str(c).rjust(w) for c, w in zip(res["columns"], widths)))
    for r in res["rows"]:
        print("  ".join(str(v).rjust(w) for v, w in zip(r, widths)))
    for note in res["notes"]:
        print("note:", note)
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
