# SPDX-License-Identifier: GPL-3.0-or-later
"""Fuzz harnesses for the Python-facing inputs: the scene JSON, the pose CSV and the mesh checks.

No atheris: a seeded random mutator over the seed corpus in tests/fuzz/corpus/<target>/ (byte
flips, inserts, deletes, splices, "interesting" numbers and tokens). Each input must either be
accepted or raise the documented error (InvalidArgumentError, a ValueError; for the CSV reader
also HapticFluidError); anything else (KeyError, TypeError, RecursionError, a warning, a crash) is a finding,
and the input that caused it is written to --crashes (default: the current folder).

    /usr/bin/python3 tests/fuzz/fuzz_inputs.py TARGET [--runs N] [--seed S] [--crashes DIR]

TARGET is scene, csv or mesh. The short run is tests/python/test_fuzz_inputs.py; the long run
(>= 10 M inputs each) is scripts/fuzz_long.sh.
"""

from __future__ import annotations

import argparse
import hashlib
import logging
import os
import random
import signal
import struct
import sys
import tempfile
import time
import traceback
import warnings
from pathlib import Path
from typing import Callable, Dict, List

import numpy as np

import hapticfluid as hf

LOG = logging.getLogger("hapticfluid.fuzz")
CORPUS = Path(__file__).resolve().parent / "corpus"
MAX_LEN = 4096

INTERESTING = [b"0", b"-1", b"1e308", b"-1e308", b"1e-320", b"nan", b"NaN", b"inf", b"-Infinity", b"null",
               b"true", b"[]", b"{}", b"\"\"", b"\x00", b"\xff", b"9" * 40, b"[[[[[[[[", b"\"adaptive\"",
               b"\"mesh\"", b"\"sphere\"", b"2147483648", b"4294967296", b",", b"\n", b"#", b"\r\n"]


# ----------------------------------------------------------------------------- the mutator

def mutate(data: bytes, corpus: List[bytes], rng: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(7)
        pos = rng.randint(0, len(b))
        if op == 0 and b:  # flip a bit
            i = rng.randrange(len(b))
            b[i] ^= 1 << rng.randrange(8)
        elif op == 1:  # insert random bytes
            b[pos:pos] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        elif op == 2 and b:  # delete a run
            del b[pos:pos + rng.randint(1, 16)]
        elif op == 3:  # insert an interesting token
            b[pos:pos] = rng.choice(INTERESTING)
        elif op == 4 and b:  # replace a digit run / token with an interesting one
            end = pos
            while end < len(b) and chr(b[end]).isalnum() | (b[end] in b".-+"):
                end += 1
            b[pos:end] = rng.choice(INTERESTING)
        elif op == 5:  # splice with another corpus entry
            other = rng.choice(corpus)
            cut = rng.randint(0, len(other))
            b[pos:] = other[cut:]
        elif op == 6 and b:  # duplicate a chunk
            start = rng.randrange(len(b))
            b[pos:pos] = b[start:start + rng.randint(1, 64)]
    return bytes(b[:MAX_LEN])


# ----------------------------------------------------------------------------- the targets

def _scene(data: bytes, tmp: Path) -> None:
    from hapticfluid.bake.scene import load_scene

    p = tmp / "scene.json"
    p.write_bytes(data)
    try:
        load_scene(p)
    except hf.InvalidArgumentError as exc:
        if not str(exc):
            raise AssertionError("InvalidArgumentError without a message") from exc


def _csv(data: bytes, tmp: Path) -> None:
    p = tmp / "pose.csv"
    p.write_bytes(data)
    try:
        dev = hf.scripted_device_from_csv(str(p))
    except hf.HapticFluidError as exc:  # InvalidArgumentError is one
        if not str(exc):
            raise AssertionError("error without a message") from exc
        return
    # An accepted script gives finite poses at its ends and in between.
    for t in (0.0, dev.duration * 0.5, dev.duration):
        if not np.all(np.isfinite(dev.state_at(t).position)):
            raise AssertionError(f"accepted script gives a non-finite position at t={t}")


def encode_mesh(vertices: np.ndarray, triangles: np.ndarray) -> bytes:
    """The mesh target's input format: uint16 vertex count, uint16 triangle count, float32 xyz rows,
    int32 ijk rows (the counts may disagree with the bytes that follow: the decoder pads/cuts)."""
    v = np.asarray(vertices, np.float32).reshape(-1, 3)
    t = np.asarray(triangles, np.int32).reshape(-1, 3)
    return struct.pack("<HH", len(v), len(t)) + v.tobytes() + t.tobytes()


def decode_mesh(data: bytes):
    if len(data) < 4:
        return np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32)
    nv, nt = struct.unpack_from("<HH", data)
    nv, nt = min(nv, 256), min(nt, 512)
    body = data[4:]
    vb = body[:nv * 12].ljust(nv * 12, b"\0")
    tb = body[nv * 12:nv * 12 + nt * 12].ljust(nt * 12, b"\0")
    return np.frombuffer(vb, np.float32).reshape(nv, 3), np.frombuffer(tb, np.int32).reshape(nt, 3)


_SIM = None


def _mesh(data: bytes, tmp: Path) -> None:
    global _SIM
    if _SIM is None:
        _SIM = hf.Simulation(resolution=(16, 16, 16), pressure_iterations=2)
    v, t = decode_mesh(data)
    m = np.eye(4)
    m[:3, 3] = 0.5
    try:
        _SIM.set_mesh_probe(v, t, transform=m)
    except hf.InvalidArgumentError as exc:
        if not str(exc):
            raise AssertionError("InvalidArgumentError without a message") from exc


TARGETS: Dict[str, Callable[[bytes, Path], None]] = {"scene": _scene, "csv": _csv, "mesh": _mesh}


def mesh_seeds() -> Dict[str, bytes]:
    from hapticfluid import meshes

    box_v, box_t = meshes.box((0.2, 0.2, 0.2))
    ico_v, ico_t = meshes.icosphere(1, 0.15)
    return {"box.bin": encode_mesh(box_v, box_t), "icosphere.bin": encode_mesh(ico_v, ico_t),
            "open_box.bin": encode_mesh(box_v, np.asarray(box_t)[:-1])}


def load_corpus(target: str) -> List[bytes]:
    folder = CORPUS / target
    seeds = [p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()] if folder.is_dir() else []
    if not seeds:
        raise SystemExit(f"no seed corpus in {folder}")
    return seeds


# ----------------------------------------------------------------------------- the run

def scratch_root() -> "str | None":
    """Where each input's file is written: /dev/shm (a RAM file system) when there is one. Opening
    and truncating a file on a busy disk cost ~8 ms an input here, 85 % of a scene input's time;
    the parser still reads a real file, so the input path is the same."""
    shm = Path("/dev/shm")
    return str(shm) if shm.is_dir() and os.access(shm, os.W_OK) else None


class Stopped(BaseException):
    """SIGTERM during a run: the run ends and reports the inputs it reached (a BaseException, so
    that the per-input handler does not take it for a finding)."""


def run(target: str, runs: int, seed: int, crashes: Path, log_every_s: float = 60.0) -> Dict[str, float]:
    """Feeds the seeds, then `runs` mutated inputs. Returns counts (with "stopped": 1 when a SIGTERM
    or Ctrl-C ended it early, "inputs" then being the count reached); raises AssertionError on a
    finding. Logs the count and rate every `log_every_s` seconds."""
    check = TARGETS[target]
    corpus = load_corpus(target)
    rng = random.Random(seed)
    start = time.perf_counter()
    next_log = start + log_every_s
    done, stopped = 0, 0
    # A warning (numpy's "overflow encountered") is a finding, as in pytest (filterwarnings = error).
    with tempfile.TemporaryDirectory(prefix=f"hf_fuzz_{target}_", dir=scratch_root()) as tmp_name, \
            warnings.catch_warnings():
        warnings.simplefilter("error")
        tmp = Path(tmp_name)
        try:
            for i in range(len(corpus) + runs):
                data = corpus[i] if i < len(corpus) else mutate(rng.choice(corpus), corpus, rng)
                try:
                    check(data, tmp)
                except Exception as exc:  # noqa: BLE001 -- any other exception is the finding
                    crashes.mkdir(parents=True, exist_ok=True)
                    out = crashes / f"crash-{target}-{hashlib.sha1(data).hexdigest()[:12]}"
                    out.write_bytes(data)
                    raise AssertionError(f"{target} input #{i} (saved to {out}) raised "
                                         f"{type(exc).__name__}: {exc}\n{traceback.format_exc()}") from exc
                done = i + 1
                now = time.perf_counter()
                if now >= next_log:
                    LOG.info("%s: %d inputs in %.0f s, %.0f/s", target, done, now - start, done / (now - start))
                    next_log = now + log_every_s
        except (KeyboardInterrupt, Stopped):
            stopped = 1
    seconds = time.perf_counter() - start
    return {"inputs": done, "seconds": seconds, "stopped": stopped}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("target", choices=sorted(TARGETS))
    p.add_argument("--runs", type=int, default=10000, help="mutated inputs after the seeds")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--crashes", type=Path, default=Path("."), help="where a failing input is saved")
    p.add_argument("--log-every", type=float, default=60.0, help="seconds between progress lines")
    args = p.parse_args(argv)

    def on_term(signum, frame):
        raise Stopped()

    signal.signal(signal.SIGTERM, on_term)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    try:
        result = run(args.target, args.runs, args.seed, args.crashes, args.log_every)
    except AssertionError as exc:
        LOG.error("%s", exc)
        return 1
    LOG.info("%s: %d inputs in %.1f s (%.0f/s), no findings%s", args.target, result["inputs"], result["seconds"],
             result["inputs"] / result["seconds"], " (stopped before the end)" if result["stopped"] else "")
    return 0


if __name__ == "__main__":
    sys.exit(main())
