# SPDX-License-Identifier: GPL-3.0-or-later
"""What every benchmark section shares: the section format, the table printer, machine facts,
statistics and the atomic JSON writer.

A section is a module ``hapticfluid.bench.<name>`` with ``run(quick: bool = False) -> dict``
returning ``{"title": str, "columns": [str, ...], "rows": [[value, ...], ...], "notes":
[str, ...]}`` (JSON values only; a cell may be ``None`` for "not applicable"). A section module
ends with::

    if __name__ == "__main__":
        raise SystemExit(report.section_main("<name>", run))

which gives it ``python3 -m hapticfluid.bench.<name> [--quick] [--json PATH]``.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import os
import platform
import subprocess
import sys
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence

from hapticfluid.files import atomic_write

REQUIRED_KEYS = ("title", "columns", "rows", "notes")
SCHEMA_VERSION = 1


# ---------------------------------------------------------------------------- statistics


def median(values: Sequence[float]) -> float:
    return quantile(values, 0.5)


def p90(values: Sequence[float]) -> float:
    return quantile(values, 0.9)


def quantile(values: Sequence[float], q: float) -> float:
    """Linear-interpolated quantile (numpy's default method) of a non-empty sequence."""
    data = sorted(float(v) for v in values)
    if not data:
        raise ValueError("quantile of no values")
    pos = q * (len(data) - 1)
    lo = math.floor(pos)
    hi = min(lo + 1, len(data) - 1)
    return data[lo] + (data[hi] - data[lo]) * (pos - lo)


# ---------------------------------------------------------------------------- section format


def check_section(name: str, result: object) -> dict:
    """Raise ValueError naming what is wrong if ``result`` is not a section result."""
    if not isinstance(result, dict):
        raise ValueError(f"section {name!r}: run() must return a dict, got {type(result).__name__}")
    missing = [k for k in REQUIRED_KEYS if k not in result]
    if missing:
        raise ValueError(f"section {name!r}: result lacks {', '.join(missing)}")
    if not isinstance(result["title"], str):
        raise ValueError(f"section {name!r}: title must be a string")
    columns = result["columns"]
    if not isinstance(columns, list) or not all(isinstance(c, str) for c in columns):
        raise ValueError(f"section {name!r}: columns must be a list of strings")
    if not isinstance(result["rows"], list):
        raise ValueError(f"section {name!r}: rows must be a list")
    for i, row in enumerate(result["rows"]):
        if not isinstance(row, list) or len(row) != len(columns):
            raise ValueError(f"section {name!r}: row {i} must be a list of {len(columns)} values")
    if not isinstance(result["notes"], list) or not all(isinstance(n, str) for n in result["notes"]):
        raise ValueError(f"section {name!r}: notes must be a list of strings")
    try:
        json.dumps(result, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"section {name!r}: result is not plain JSON ({exc})") from None
    return result


def column(result: dict, name: str) -> List[object]:
    """The values of one named column of a section result."""
    try:
        i = result["columns"].index(name)
    except ValueError:
        raise KeyError(f"no column {name!r} in {result['columns']}") from None
    return [row[i] for row in result["rows"]]


def finite_or_none(value: Optional[float]) -> Optional[float]:
    """JSON has no NaN/inf: those become None (printed as '-')."""
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None


# ---------------------------------------------------------------------------- table printing


def format_value(value: object) -> str:
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return f"{value:,}".replace(",", " ") if abs(value) >= 100000 else str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        a = abs(value)
        if a == 0.0:
            return "0"
        if a >= 1000:
            return f"{value:.0f}"
        if a >= 100:
            return f"{value:.1f}"
        if a >= 1:
            return f"{value:.2f}"
        if a >= 0.01:
            return f"{value:.3f}"
        return f"{value:.2e}"
    return str(value)


def format_table(result: dict, markdown: bool = False) -> str:
    """The section as a text table (or a Markdown table), notes underneath."""
    header = [str(c) for c in result["columns"]]
    body = [[format_value(v) for v in row] for row in result["rows"]]
    lines: List[str] = []
    if markdown:
        lines.append(f"**{result['title']}**")
        lines.append("")
        lines.append("| " + " | ".join(header) + " |")
        lines.append("|" + "|".join("---" for _ in header) + "|")
        lines.extend("| " + " | ".join(row) + " |" for row in body)
        if result["notes"]:
            lines.append("")
            lines.extend(f"- {note}" for note in result["notes"])
        return "\n".join(lines)
    widths = [len(h) for h in header]
    for row in body:
        widths = [max(w, len(cell)) for w, cell in zip(widths, row)]

    def fmt(cells: Sequence[str]) -> str:
        # Text left, numbers right.
        out = []
        for i, cell in enumerate(cells):
            numeric = all(_looks_numeric(r[i]) for r in body) if body else False
            out.append(cell.rjust(widths[i]) if numeric else cell.ljust(widths[i]))
        return "  ".join(out).rstrip()

    lines.append(result["title"])
    lines.append("=" * len(result["title"]))
    lines.append(fmt(header))
    lines.append("  ".join("-" * w for w in widths))
    lines.extend(fmt(row) for row in body)
    if not body:
        lines.append("(no rows)")
    for note in result["notes"]:
        lines.append(f"* {note}")
    return "\n".join(lines)


def _looks_numeric(text: str) -> bool:
    if text == "-":
        return True
    try:
        float(text.replace(" ", ""))
        return True
    except ValueError:
        return False


# ---------------------------------------------------------------------------- machine facts


def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.lower().startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def git_commit() -> Optional[str]:
    """The commit of the source tree this package came from (None outside a git checkout)."""
    here = Path(__file__).resolve().parent
    try:
        commit = subprocess.run(["git", "-C", str(here), "rev-parse", "HEAD"], capture_output=True,
                                text=True, timeout=10, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(here), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10, check=True).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + ("-dirty" if dirty else "") if commit else None


def machine_info(device: str = "") -> Dict[str, object]:
    """CPU, memory, GL device (hapticfluid.probe_device), date and commit of this run."""
    import hapticfluid as hf

    info: Dict[str, object] = {
        "date_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "cpu_model": cpu_model(),
        "cpu_cores": os.cpu_count(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        "hapticfluid": hf.__version__,
        "git_commit": git_commit(),
    }
    try:
        info["load_average_1_5_15"] = [round(x, 2) for x in os.getloadavg()]
    except OSError:
        pass
    try:
        with open("/proc/meminfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    info["memory_bytes"] = int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    gl = hf.probe_device(device)
    info["gl_renderer"] = gl.get("renderer")
    info["gl_vendor"] = gl.get("vendor")
    info["gl_version"] = gl.get("version")
    info["gl_software"] = gl.get("software")
    info["gl_memory_bytes"] = gl.get("memory_bytes")
    return info


def describe_machine(info: Dict[str, object]) -> str:
    load = info.get("load_average_1_5_15")
    return (f"{info.get('date_utc')}  {info.get('cpu_model')} x{info.get('cpu_cores')}  "
            f"GL: {info.get('gl_renderer')} ({info.get('gl_version')})  "
            f"commit {info.get('git_commit') or 'unknown'}"
            + (f"  load {load}" if load else ""))


# ---------------------------------------------------------------------------- output files


def write_json_atomic(path: os.PathLike, data: object) -> Path:
    """Write ``data`` as JSON through a temporary file in the same folder, then rename it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(data, indent=2, allow_nan=False) + "\n"
    return atomic_write(path, lambda f: f.write(text))


def document(sections: Dict[str, dict], quick: bool, machine: Dict[str, object]) -> dict:
    """The JSON document the bench command and every section's __main__ write."""
    return {"schema": SCHEMA_VERSION, "quick": quick, "machine": machine, "sections": sections}


def section_main(name: str, run: Callable[..., dict], argv: Optional[Sequence[str]] = None) -> int:
    """``python3 -m hapticfluid.bench.<name> [--quick] [--json PATH]``: run, print, write."""
    import hapticfluid as hf

    parser = argparse.ArgumentParser(prog=f"python3 -m hapticfluid.bench.{name}",
                                     description=f"Run the {name!r} benchmark section alone.")
    parser.add_argument("--quick", action="store_true", help="small sizes (a test run)")
    parser.add_argument("--json", metavar="PATH", help="also write the results to this JSON file")
    args = parser.parse_args(argv)
    try:
        machine = machine_info()
        print(describe_machine(machine), flush=True)
        result = check_section(name, run(quick=args.quick))
        print(format_table(result), flush=True)
        if args.json:
            write_json_atomic(args.json, document({name: result}, args.quick, machine))
            print(f"wrote {args.json}")
    except (hf.HapticFluidError, OSError, ValueError) as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 1
    return 0


def progress(line: str) -> None:
    """Progress of a long section, on stderr (stdout carries the tables)."""
    print(line, file=sys.stderr, flush=True)
