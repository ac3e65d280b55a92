# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid bench``: run the benchmark sections, print a table for each, write
all results (with the machine's description) to one JSON file.

The sections are the modules ``hapticfluid.bench.<name>`` listed in ``SECTIONS``; each has
``run(quick: bool = False) -> dict`` (format: :mod:`hapticfluid.bench.report`). A listed section
whose module is missing is an error, never skipped. A section that fails is reported, its error
kept in the JSON, the other sections still run, and the command exits 1.
"""

from __future__ import annotations

import argparse
import importlib
import os
import time
import traceback
from typing import Dict, List, Optional, Sequence

import hapticfluid as hf
from hapticfluid.bench import report

# Section modules, run in this order. Add a section by appending its module name.
SECTIONS: List[str] = ["engine", "backends", "readback", "mantaflow", "voxelize", "haptic", "bake", "checkpoint",
                       "pressure", "force_roughness", "floor"]

DEFAULT_JSON = os.path.join("out", "bench", "bench.json")


def load_section(name: str):
    """The section's module; HapticFluidError if it is listed but missing or has no run()."""
    module_name = f"hapticfluid.bench.{name}"
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name == module_name:
            raise hf.HapticFluidError(
                f"benchmark section {name!r} is listed in hapticfluid.bench.runner.SECTIONS but "
                f"its module python/hapticfluid/bench/{name}.py is missing") from None
        raise
    if not callable(getattr(module, "run", None)):
        raise hf.HapticFluidError(f"benchmark section module {module_name} has no run(quick) function")
    return module


def _section_list(text: str) -> List[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise argparse.ArgumentTypeError("expected a comma-separated list of section names")
    unknown = [n for n in names if n not in SECTIONS]
    if unknown:
        raise argparse.ArgumentTypeError(
            f"unknown section(s) {', '.join(unknown)}; the sections are {', '.join(SECTIONS)}")
    return list(dict.fromkeys(names))


def add_parser(sub) -> None:
    p = sub.add_parser(
        "bench",
        help="run the benchmarks; print tables, write JSON",
        description="Run the benchmark sections (%s), print one table per section and write "
                    "all results with the machine's description to a JSON file. Timings depend "
                    "on what else the machine is doing." % ", ".join(SECTIONS))
    p.add_argument("--sections", type=_section_list, default=None, metavar="A,B",
                   help="run only these sections (default: all)")
    p.add_argument("--quick", action="store_true",
                   help="small grids and few steps (a smoke test, seconds per section)")
    p.add_argument("--json", default=DEFAULT_JSON, metavar="PATH",
                   help="results file, written atomically (default: %(default)s)")
    p.add_argument("--plot", default=None, metavar="PNG",
                   help="also draw ms per step against cell count (engine section) to PNG")
    p.add_argument("--replot", action="store_true",
                   help="run nothing: draw --plot from the results already in --json")
    p.add_argument("--markdown", action="store_true", help="print the tables as Markdown")
    p.add_argument("--show", action="store_true",
                   help="run nothing: print the tables of the results already in --json (e.g. a committed "
                        "docs/bench_results*.json), under the machine, date and commit they were measured on")
    p.set_defaults(func=cmd_bench)


def run_sections(names: Sequence[str], quick: bool, log=report.progress) -> Dict[str, dict]:
    """Run sections in order; a failing section becomes {"error": message} and the rest go on."""
    modules = {name: load_section(name) for name in names}  # every missing module first
    results: Dict[str, dict] = {}
    for name, module in modules.items():
        t0 = time.perf_counter()
        try:
            result = report.check_section(name, module.run(quick=quick))
        except (hf.HapticFluidError, OSError, ValueError, RuntimeError) as exc:
            log(f"bench: section {name!r} failed: {exc}")
            if not isinstance(exc, hf.HapticFluidError):
                log(traceback.format_exc().rstrip())
            results[name] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        result["seconds"] = round(time.perf_counter() - t0, 2)
        results[name] = result
    return results


def show(path: "str | os.PathLike", markdown: bool = False, sections: Optional[Sequence[str]] = None) -> str:
    """The tables of a results file, under the machine line (date, load, commit) they were
    measured with: the figures the docs quote, regenerated from the raw result."""
    import json

    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, ValueError) as exc:
        raise hf.InvalidArgumentError(f"--json {os.fspath(path)!r} cannot be read as a results file: {exc}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("sections"), dict):
        raise hf.InvalidArgumentError(f"--json {os.fspath(path)!r} is not a benchmark results file (no 'sections')")
    machine = doc.get("machine") or {}
    parts = [f"{report.describe_machine(machine)}{'  (quick run)' if doc.get('quick') else ''}"]
    for name, result in doc["sections"].items():
        if sections and name not in sections:
            continue
        parts.append(f"{name}: FAILED: {result['error']}" if "error" in result
                     else report.format_table(result, markdown=markdown))
    return "\n\n".join(parts)


def cmd_bench(args: argparse.Namespace) -> int:
    from hapticfluid.bench import plot as _plot

    if args.show:
        print(show(args.json, markdown=args.markdown, sections=args.sections))
        return 0
    if args.replot:
        if not args.plot:
            raise hf.InvalidArgumentError("--replot needs --plot PNG")
        _plot.plot_file(args.json, args.plot)
        print(f"wrote {args.plot}")
        return 0
    names = args.sections or SECTIONS
    if args.plot and "engine" not in names:
        raise hf.InvalidArgumentError("--plot draws the engine section's results; add engine to --sections")
    machine = report.machine_info()
    print(report.describe_machine(machine), flush=True)
    results = run_sections(names, args.quick)
    failed = [n for n, r in results.items() if "error" in r]
    for name, result in results.items():
        print()
        if "error" in result:
            print(f"{name}: FAILED: {result['error']}")
        else:
            print(report.format_table(result, markdown=args.markdown), flush=True)
    report.write_json_atomic(args.json, report.document(results, args.quick, machine))
    print(f"\nwrote {args.json}")
    if args.plot:
        if "error" in results["engine"]:
            print("no plot: the engine section failed")
        else:
            _plot.plot_results(results["engine"], args.plot, machine)
            print(f"wrote {args.plot}")
    if failed:
        print(f"failed sections: {', '.join(failed)}")
        return 1
    return 0

