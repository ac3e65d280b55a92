# SPDX-License-Identifier: GPL-3.0-or-later
"""The benchmark plot: wall ms per step against cell count, one line per pressure solver, from
the engine section's results (log-log, with the seed's 30 FPS and the haptic 1 kHz lines).

Regenerate it from a results file::

    python3 -m hapticfluid.bench.plot [--json out/bench/bench.json] [--out docs/bench_ms_per_step.png]

(the same as ``python3 -m hapticfluid bench --replot --json ... --plot ...``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple

from hapticfluid.bench import report
from hapticfluid.files import atomic_write

DEFAULT_PNG = os.path.join("docs", "bench_ms_per_step.png")


def series(engine: dict) -> Dict[str, List[Tuple[int, float, float, str]]]:
    """Per solver: (cells, median ms, p90 ms, grid label), sorted by cells."""
    out: Dict[str, List[Tuple[int, float, float, str]]] = {}
    for grid, cells, solver, med, p90 in zip(report.column(engine, "grid"), report.column(engine, "cells"),
                                              report.column(engine, "solver"),
                                              report.column(engine, "wall ms median"),
                                              report.column(engine, "wall ms p90")):
        out.setdefault(str(solver), []).append((int(cells), float(med), float(p90), str(grid)))
    for points in out.values():
        points.sort()
    return out


def plot_results(engine: dict, png: os.PathLike, machine: Optional[dict] = None) -> Path:
    """Draw the engine section's ms per step against cells into ``png`` (written atomically)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    data = series(engine)
    if not data:
        raise ValueError("the engine section has no rows to plot")
    fig = Figure(figsize=(8.0, 5.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    lowest: Dict[str, Tuple[float, float]] = {}  # grid -> (cells, lowest median ms): one label per grid
    for solver, points in data.items():
        cells = [p[0] for p in points]
        med = [p[1] for p in points]
        p90 = [p[2] for p in points]
        line, = ax.plot(cells, med, marker="o", label=f"{solver} (median)")
        ax.plot(cells, p90, linestyle=":", color=line.get_color(), label=f"{solver} (p90)")
        for c, m, _, grid in points:
            if grid not in lowest or m < lowest[grid][1]:
                lowest[grid] = (c, m)
    for grid, (c, m) in lowest.items():
        ax.annotate(grid, (c, m), textcoords="offset points", xytext=(5, -12), fontsize=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    all_cells = [c for c, _ in lowest.values()]
    ax.set_xlim(min(all_cells) / 1.4, max(all_cells) * 1.8)  # room for the last label
    ax.axhline(1000.0 / 30.0, color="grey", linestyle="--", linewidth=1)
    # x in axes fraction, y in data: the label sits at the left edge whatever the cell range.
    ax.text(0.01, 1000.0 / 30.0, "30 steps/s (seed: 30-75 FPS at 100x100x70 on a 2008 GPU)",
            transform=ax.get_yaxis_transform(), va="bottom", fontsize=8, color="grey")
    targets = [(128 ** 3, 1.0), (256 ** 3, 5.0)]
    ax.plot([c for c, _ in targets], [ms for _, ms in targets], linestyle="none", marker="x",
            color="black", label="H100 targets (not measured here)")
    ax.set_xlabel("cells")
    ax.set_ylabel("wall ms per step")
    title = "hapticfluid: ms per simulation step"
    if machine:
        title += f"\n{machine.get('gl_renderer')}, {machine.get('cpu_model')} x{machine.get('cpu_cores')}, " \
                 f"{str(machine.get('date_utc', ''))[:10]}"
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    png = Path(png)
    png.parent.mkdir(parents=True, exist_ok=True)
    return atomic_write(png, lambda f: fig.savefig(f, format="png", dpi=110), binary=True)


def plot_file(json_path: os.PathLike, png: os.PathLike) -> Path:
    """Draw the plot from a results file written by the bench command."""
    with open(json_path, encoding="utf-8") as f:
        doc = json.load(f)
    engine = doc.get("sections", {}).get("engine")
    if not engine or "error" in engine:
        raise ValueError(f"{json_path} has no engine section results to plot")
    return plot_results(engine, png, doc.get("machine"))


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m hapticfluid.bench.plot",
                                     description="Draw ms per step against cells from bench JSON.")
    parser.add_argument("--json", default=os.path.join("out", "bench", "bench.json"), metavar="PATH")
    parser.add_argument("--out", default=DEFAULT_PNG, metavar="PNG")
    args = parser.parse_args(argv)
    try:
        plot_file(args.json, args.out)
    except (OSError, ValueError, KeyError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 1
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
