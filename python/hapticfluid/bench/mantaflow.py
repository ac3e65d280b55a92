# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``mantaflow``: Blender's built-in Mantaflow smoke against this engine on the
same scene, machine and run, in two comparisons: the step loop (:mod:`hapticfluid.bench.mantaflow_loop`:
one step and a ``density()`` read-back per frame on the seed paper's 100 x 100 x 70 grid) and
the bake command as a user runs it (:mod:`hapticfluid.bench.mantaflow_bake`: ``python3 -m
hapticfluid bake``, files written, converged solver, closed box at 24 fps). The column
``comparison`` tells them apart: ``step loop`` and ``bake command``. Each module documents its
method.

Run alone: ``python3 -m hapticfluid.bench.mantaflow [--quick] [--json PATH]``.
"""

from __future__ import annotations

from hapticfluid.bench import mantaflow_bake, mantaflow_loop, report
from hapticfluid.bench.mantaflow_loop import COLUMNS


def run(quick: bool = False, log=report.progress) -> dict:
    """Both comparisons: the step loop's rows, then the bake command's (column ``comparison``)."""
    loop = mantaflow_loop.run_step_loop(quick, log)
    bake = mantaflow_bake.run(quick, log)
    rows = [["step loop", *row] for row in loop["rows"]] + [["bake command", *row] for row in bake["rows"]]
    notes = [f"step loop: {n}" for n in loop["notes"]] + [f"bake command: {n}" for n in bake["notes"]]
    return {"title": "Mantaflow (Blender) against this engine (step loop; bake command), same machine",
            "columns": ["comparison", *COLUMNS], "rows": rows, "notes": notes}


if __name__ == "__main__":
    raise SystemExit(report.section_main("mantaflow", run))
