# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark section ``checkpoint``: what a bake's checkpoint costs at each resolution.

For the benchmark scene at 64^3, 128^3 and 192^3 (quick: 16^3 and 24^3) after a step:
``Simulation.state()`` (the read-back the frame file and the checkpoint share), writing the
checkpoint (``cache.save_checkpoint``: the zip's CRC-32 of every array as it is written, fsync, rename),
keeping it (``cache.keep_checkpoint``: a hard link, what every K-th frame adds), and loading it
back with every CRC checked (``cache.load_checkpoint``: what a re-bake pays once). Bytes on
disk beside the estimate the add-on shows (``cache.checkpoint_bytes``). Times are medians over
repeats; the disk is the temporary folder's.

Run alone: ``python3 -m hapticfluid.bench.checkpoint [--quick] [--json PATH]``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path
from typing import Callable, List, Tuple

from hapticfluid.bake import cache as _cache
from hapticfluid.bench import report
from hapticfluid.bench.scene import BenchScene

FULL_GRIDS = (64, 128, 192)
QUICK_GRIDS = (16, 24)
FULL_REPEATS = 3
QUICK_REPEATS = 2

COLUMNS = ["grid", "MB on disk", "MB estimated", "state() ms", "write ms", "write MB/s", "keep ms", "load ms"]


def _ms(fn: Callable[[], object], repeats: int) -> Tuple[float, object]:
    times: List[float] = []
    out = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append((time.perf_counter() - t0) * 1000.0)
    return report.median(times), out


def run(quick: bool = False, log=report.progress) -> dict:
    grids = QUICK_GRIDS if quick else FULL_GRIDS
    repeats = QUICK_REPEATS if quick else FULL_REPEATS
    fingerprint = {"benchmark": "checkpoint"}
    rows = []
    with tempfile.TemporaryDirectory(prefix="hf_bench_checkpoint_") as tmp:
        for n in grids:
            scene = BenchScene((n, n, n), (1.0, 1.0, 1.0))
            if log:
                log(f"checkpoint: {scene.label} ...")
            cache = Path(tmp) / f"c{n}"
            (cache / _cache.CHECKPOINT_DIR).mkdir(parents=True)
            with scene.make_simulation() as sim:
                scene.step(sim)
                state_ms, state = _ms(sim.state, repeats)
            write_ms, _ = _ms(lambda: _cache.save_checkpoint(cache, 10, state, fingerprint, inputs_sha256="0" * 64),
                              repeats)
            keep_ms, _ = _ms(lambda: _cache.keep_checkpoint(cache, 10), repeats)
            load_ms, _ = _ms(lambda: _cache.load_checkpoint(cache, fingerprint, path=_cache.kept_checkpoint_path(cache, 10)),
                             repeats)
            size = _cache.checkpoint_path(cache).stat().st_size
            estimate = _cache.checkpoint_bytes((n, n, n))
            rows.append([f"{n}^3", round(size / 1e6, 3), round(estimate / 1e6, 3), round(state_ms, 1),
                         round(write_ms, 1), round(size / 1e6 / (write_ms / 1000.0), 1), round(keep_ms, 2),
                         round(load_ms, 1)])
            del state
    return {
        "title": "Checkpoint: size and time per checkpoint (benchmark scene after one step)",
        "columns": COLUMNS,
        "rows": rows,
        "notes": ["write: SHA-256 of each array while written, fsync, rename (on the writer thread, beside the "
                  "next frame's steps); every frame writes one",
                  "keep: a hard link to the latest checkpoint, what every K-th frame adds (scene "
                  "cache.checkpoint_every)",
                  "load: read and check every array's digest: what a re-bake from a kept checkpoint pays once",
                  "MB estimated: cache.checkpoint_bytes, the figure the add-on's Cache panel shows",
                  "times depend on the disk and the machine's load; take them as indications"],
    }


if __name__ == "__main__":
    raise SystemExit(report.section_main("checkpoint", run))
