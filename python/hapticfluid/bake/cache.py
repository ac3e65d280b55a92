# SPDX-License-Identifier: GPL-3.0-or-later
"""Where a bake's files go, and how each is written so that a kill never corrupts one.

Layout (like Mantaflow's OpenVDB cache, so tools that know Blender's fluid caches find it)::

    <cache>/data/fluid_data_####.vdb     one file per frame (frame number, 4 digits)
    <cache>/checkpoint/state.npz         the simulation state after the last complete frame
    <cache>/checkpoint/state_####.npz    kept checkpoints: the state after every K-th frame
                                         (scene cache.checkpoint_every), and after the last
                                         frame of a bake stopped with ``until`` (a farm chunk)
    <cache>/hapticfluid_bake.json        the manifest: scene settings, frames done with what
                                         each consumed (plan.py), kept checkpoints, timings

Every file is written under a temporary name in its own folder and renamed into place when
complete (a rename within a folder is atomic), so each path holds either its old content or
its new one. The checkpoint carries a SHA-256 of each array and of the scene's settings and
inputs up to its frame, so a damaged checkpoint, or one from other settings or other keys, is
refused with a clear error. A kept checkpoint is a hard link to the latest one as written (no
second write: the next frame's checkpoint replaces the latest by a rename, a new file), or a
copy where the file system has no hard links.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import re
import tempfile
import time
import zipfile
from pathlib import Path
from typing import Any, Callable, Dict, Iterator, List, Optional, Tuple

import numpy as np

import hapticfluid
from hapticfluid import HapticFluidError
from hapticfluid.files import atomic_write

DATA_DIR = "data"
CHECKPOINT_DIR = "checkpoint"
CHECKPOINT_FILE = "state.npz"
KEPT_PATTERN = re.compile(r"^state_(\d{4})\.npz$")
MANIFEST_FILE = "hapticfluid_bake.json"
FRAME_PREFIX = "fluid_data_"
FRAME_PATTERN = re.compile(r"^fluid_data_(\d{4})\.vdb$")
# 3: each array's integrity is its zip member's CRC-32 (checked as it is read back); 2: also a
# SHA-256 per array in its memory order; 1: the SHA-256 in C order. All three are read.
CHECKPOINT_FORMAT = 3
READABLE_CHECKPOINT_FORMATS = (1, 2, 3)


class BakeError(HapticFluidError):
    """A bake cannot start or continue: cache folder, checkpoint or manifest problems."""


def frame_path(cache_dir: "str | os.PathLike", frame: int) -> Path:
    return Path(cache_dir) / DATA_DIR / f"{FRAME_PREFIX}{frame:04d}.vdb"


def checkpoint_path(cache_dir: "str | os.PathLike") -> Path:
    return Path(cache_dir) / CHECKPOINT_DIR / CHECKPOINT_FILE


def kept_checkpoint_path(cache_dir: "str | os.PathLike", frame: int) -> Path:
    return Path(cache_dir) / CHECKPOINT_DIR / f"state_{frame:04d}.npz"


def manifest_path(cache_dir: "str | os.PathLike") -> Path:
    return Path(cache_dir) / MANIFEST_FILE


def checkpoint_bytes(cells: "Tuple[int, int, int]") -> int:
    """Bytes of one checkpoint for a grid of ``cells``: the six float32 state arrays (three
    velocity components on faces, density, temperature, pressure) and about 4 KB of zip
    headers and metadata."""
    nx, ny, nz = (int(n) for n in cells)
    values = (nx + 1) * ny * nz + nx * (ny + 1) * nz + nx * ny * (nz + 1) + 3 * nx * ny * nz
    return 4 * values + 4096


def list_kept_checkpoints(cache_dir: "str | os.PathLike") -> List[int]:
    """Frames of the kept checkpoints (checkpoint/state_####.npz), ascending."""
    try:
        names = os.listdir(Path(cache_dir) / CHECKPOINT_DIR)
    except (FileNotFoundError, NotADirectoryError):
        return []
    return sorted(int(m.group(1)) for m in (KEPT_PATTERN.match(name) for name in names) if m)


def keep_checkpoint(cache_dir: "str | os.PathLike", frame: int) -> Path:
    """Keep the latest checkpoint (which must be frame ``frame``'s) as state_####.npz: a hard
    link made under a temporary name and renamed into place (atomic), or a copy where links
    are refused."""
    import shutil

    from hapticfluid.files import sync_folder

    latest = checkpoint_path(cache_dir)
    kept = kept_checkpoint_path(cache_dir, frame)
    tmp = kept.with_name(f".{kept.name}.{os.getpid()}.tmp")
    try:
        try:
            os.link(latest, tmp)
        except FileExistsError:
            os.unlink(tmp)
            os.link(latest, tmp)
        except OSError:  # no hard links here (some network and FAT file systems): a copy
            shutil.copyfile(latest, tmp)
        os.replace(tmp, kept)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    sync_folder(kept.parent)
    return kept


def remove_checkpoints_from(cache_dir: "str | os.PathLike", frame: int) -> List[int]:
    """Delete the kept checkpoints of frames >= ``frame`` and the latest one if it is of such a
    frame (they hold states the frames being re-baked will change); returns their frames."""
    removed = []
    for f in list_kept_checkpoints(cache_dir):
        if f >= frame:
            kept_checkpoint_path(cache_dir, f).unlink()
            removed.append(f)
    latest = checkpoint_path(cache_dir)
    at = checkpoint_frame(latest)
    if at is not None and at >= frame:
        latest.unlink()
    return removed


def checkpoint_frame(path: "str | os.PathLike") -> Optional[int]:
    """The frame a checkpoint file holds the state after, read from its metadata only; None if
    the file is missing or unreadable (load_checkpoint says why)."""
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:  # reads the meta member only
            return int(json.loads(bytes(z["meta"]).decode())["frame"])
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError, UnicodeDecodeError, TypeError):
        return None


def list_frames(cache_dir: "str | os.PathLike") -> List[int]:
    """Frame numbers of the complete frame files in the cache (temporary files excluded); none
    if there is no data folder. Safe beside a running bake: a fresh bake frees the cache (its
    empty data folder removed) and makes the folder again, so the folder can vanish between a
    check and the listing (a test polling a starting bake met it once, in a fresh-clone run of
    the README's test command)."""
    try:
        names = os.listdir(Path(cache_dir) / DATA_DIR)
    except (FileNotFoundError, NotADirectoryError):
        return []
    return sorted(int(m.group(1)) for m in (FRAME_PATTERN.match(name) for name in names) if m)


def prepare_cache(cache_dir: "str | os.PathLike") -> Path:
    """Make ``<cache>/data`` and ``<cache>/checkpoint`` and prove they are writable, before any
    simulation work. The cache folder itself may be created, its parent must exist."""
    if "\0" in os.fspath(cache_dir):
        raise BakeError(f"cache folder {os.fspath(cache_dir)!r} holds a NUL character; give a real folder path")
    cache = Path(cache_dir)
    parent = cache.absolute().parent
    if not cache.exists() and not parent.is_dir():
        raise BakeError(f"cache folder '{cache}' cannot be made: its parent folder '{parent}' does not exist; "
                        "create it or choose another cache folder")
    if cache.exists() and not cache.is_dir():
        raise BakeError(f"cache path '{cache}' exists and is not a folder; choose a folder")
    try:
        for sub in (cache, cache / DATA_DIR, cache / CHECKPOINT_DIR):
            sub.mkdir(exist_ok=True)
            fd, probe = tempfile.mkstemp(prefix=".write-test.", dir=sub)
            os.close(fd)
            os.unlink(probe)
    except OSError as exc:
        raise BakeError(f"cache folder '{cache}' is not writable ({exc.strerror or exc}); "
                        "choose a folder you can write to") from None
    return cache


def check_frames_are_ours(cache_dir: "str | os.PathLike") -> None:
    """BakeError if the folder holds frame files but no manifest. A bake writes its manifest
    before its first frame, so such frames come from elsewhere: the layout is Mantaflow's, and a
    Blender fluid cache chosen as the folder would otherwise be deleted."""
    frames = list_frames(cache_dir)
    if frames and not manifest_path(cache_dir).exists():
        raise BakeError(f"cache folder '{Path(cache_dir)}' holds {len(frames)} frame file(s) "
                        f"({DATA_DIR}/{FRAME_PREFIX}####.vdb) but no {MANIFEST_FILE}, so no hapticfluid bake "
                        "wrote them (a Mantaflow cache?); they are not deleted: choose another cache folder "
                        "or remove them yourself")


LOCK_FILE = ".hapticfluid_bake.lock"


@contextlib.contextmanager
def bake_lock(cache_dir: "str | os.PathLike") -> Iterator[None]:
    """Hold the cache folder's lock for a bake: a second bake into the same folder (another
    thread, process or Blender) gets a BakeError instead of interleaving its frames and
    checkpoints with this one's. The kernel drops the lock when the process dies (SIGKILL too),
    so a killed bake never leaves the folder locked."""
    import fcntl

    path = Path(cache_dir) / LOCK_FILE
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise BakeError(f"another bake is running in the cache folder '{Path(cache_dir)}' (it holds "
                            f"{LOCK_FILE}); wait for it or cancel it, or choose another folder") from None
        yield
    finally:
        os.close(fd)  # releases the lock


def free_cache(cache_dir: "str | os.PathLike") -> int:
    """Delete the bake's own files (frames, checkpoint, manifest, stale temporaries); returns
    how many. Other files in the folder are left alone, and frames that no hapticfluid bake
    wrote are refused (BakeError, see check_frames_are_ours) before anything is deleted, as is
    a folder another bake is running in (bake_lock)."""
    if not Path(cache_dir).is_dir():
        return 0
    with bake_lock(cache_dir):
        return free_cache_locked(cache_dir)


def free_cache_locked(cache_dir: "str | os.PathLike") -> int:
    """free_cache for a caller that holds bake_lock already (the bake driver)."""
    cache = Path(cache_dir)
    check_frames_are_ours(cache)
    removed = 0
    candidates = []
    for folder, pattern in ((cache / DATA_DIR, FRAME_PATTERN), (cache / CHECKPOINT_DIR, None), (cache, None)):
        if not folder.is_dir():
            continue
        for p in folder.iterdir():
            name = p.name
            ours = (pattern is not None and pattern.match(name)) or name in (CHECKPOINT_FILE, MANIFEST_FILE) \
                or (folder.name == CHECKPOINT_DIR and KEPT_PATTERN.match(name)) or _is_our_temporary(name)
            if ours and p.is_file():
                candidates.append(p)
    for p in candidates:
        p.unlink()
        removed += 1
    for folder in (cache / DATA_DIR, cache / CHECKPOINT_DIR):
        try:
            folder.rmdir()  # only if now empty
        except OSError:
            pass
    return removed


def _is_our_temporary(name: str) -> bool:
    """A temporary file of a frame, a checkpoint (latest or kept) or the manifest."""
    return name.startswith(".") and name.endswith(".tmp") and (
        name.startswith(f".{FRAME_PREFIX}") or name.startswith(f".{CHECKPOINT_FILE}.")
        or name.startswith(f".{MANIFEST_FILE}.") or KEPT_PATTERN.match(name[1:].split(".npz.")[0] + ".npz") is not None)


def remove_temporaries(cache_dir: "str | os.PathLike") -> int:
    """Delete temporary files a killed bake left behind (never a complete file); returns how many."""
    cache = Path(cache_dir)
    removed = 0
    for folder in (cache, cache / DATA_DIR, cache / CHECKPOINT_DIR):
        if not folder.is_dir():
            continue
        for p in folder.iterdir():
            if _is_our_temporary(p.name) and p.is_file():
                p.unlink()
                removed += 1
    return removed


# ---- manifest ------------------------------------------------------------------------------

def write_manifest(cache_dir: "str | os.PathLike", manifest: Dict[str, Any]) -> None:
    path = manifest_path(cache_dir)
    atomic_write(path, lambda f: json.dump(manifest, f, indent=2, sort_keys=True))


def read_manifest(cache_dir: "str | os.PathLike") -> Optional[Dict[str, Any]]:
    path = manifest_path(cache_dir)
    if not path.exists():
        return None
    fix = ("resume the bake (--resume) to rewrite it: resume needs only the checkpoint and checks every frame "
           "file; or free the cache and bake again")
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError) as exc:  # ValueError: bad JSON, not UTF-8, huge ints
        raise BakeError(f"bake manifest '{path}' cannot be read ({type(exc).__name__}: {exc}); {fix}") from None
    if not isinstance(manifest, dict):
        raise BakeError(f"bake manifest '{path}' is not a JSON object (it holds a {type(manifest).__name__}); {fix}")
    return manifest


def manifest_records(manifest: Optional[Dict[str, Any]]) -> Dict[int, Dict[str, Any]]:
    """The manifest's per-frame records by frame number ({} if it has none or they are malformed)."""
    raw = manifest.get("frame_records") if isinstance(manifest, dict) else None
    if not isinstance(raw, dict):
        return {}
    out: Dict[int, Dict[str, Any]] = {}
    for key, value in raw.items():
        try:
            frame = int(key)
        except (TypeError, ValueError):
            continue
        if isinstance(value, dict):
            out[frame] = value
    return out


class BakeManifest:
    """The cache's manifest as one bake session writes it: the scene and its inputs
    (plan.InputsLedger), every frame done with its record (size, SHA-256 and the inputs it
    consumed), the kept checkpoints, and one entry per bake session. A session whose plan keeps
    the frames before its first frame to write keeps their records and the earlier sessions'
    entries from ``previous`` (the manifest read before the bake). record_frame() runs on the
    writer thread, one frame after the other; save() writes the manifest whole (atomic)."""

    def __init__(self, cache_dir: "str | os.PathLike", scene: Any, ledger: Any,
                 previous: Optional[Dict[str, Any]] = None) -> None:
        self.cache_dir = Path(cache_dir)
        self._scene, self._ledger, self._previous = scene, ledger, previous or {}
        self.data: Dict[str, Any] = {
            "format": "hapticfluid-bake",
            "hapticfluid_version": hapticfluid.__version__,
            "openvdb_version": hapticfluid.openvdb_version(),
            "scene": scene.to_dict(),
            "inputs": ledger.manifest_entry(),
            "frame_files": f"{DATA_DIR}/{FRAME_PREFIX}####.vdb",
            "frames_done": [],
            "last_frame": None,
            "complete": False,
            "checkpoint_every": scene.checkpoint_every,
            "checkpoints": [],
            "sessions": [],
            "frame_records": {},
        }
        self.session: Dict[str, Any] = {}
        self._t0 = time.perf_counter()  # the session's seconds count from here

    def start_session(self, plan: Any, resumed_from: Optional[int], device: Optional[str]) -> None:
        """This session's entry (the plan's text, the checkpoint it resumed from, the GL device)
        and the frames the plan keeps with their records (a legacy cache's records get their
        inputs: they matched its checkpoint). Then the cache is made ready for the first frame to
        write: a plan that keeps no frame frees the earlier bake; one that does removes the
        checkpoints from that frame on (states the re-bake changes). Saves nothing."""
        scene, write_from = self._scene, plan.first_frame
        if plan.keeps_frames:
            sessions = self._previous.get("sessions", [])
            self.data["sessions"] = list(sessions) if isinstance(sessions, list) else []
            self.data["frames_done"] = list(range(scene.frame_start, write_from))
            self.data["frame_records"] = {str(f): r for f, r in manifest_records(self._previous).items()
                                          if scene.frame_start <= f < write_from}
            for f in self.data["frames_done"]:
                self.data["frame_records"].setdefault(str(f), {}).setdefault("inputs", self._ledger.frames[f])
            remove_checkpoints_from(self.cache_dir, write_from)
        else:
            free_cache_locked(self.cache_dir)
            prepare_cache(self.cache_dir)
        self.data["last_frame"] = plan.last_kept_frame
        self.session = {"started_unix": time.time(), "resumed_from": resumed_from, "frames": 0, "seconds": 0.0,
                        "device": device, "plan": plan.text}
        if plan.damaged:
            self.session["rebaked_damaged_frames"] = sorted(plan.damaged)
        self.data["sessions"].append(self.session)
        self.data["checkpoints"] = [{"frame": f, "bytes": kept_checkpoint_path(self.cache_dir, f).stat().st_size}
                                    for f in list_kept_checkpoints(self.cache_dir)]

    @property
    def last_frame(self) -> Optional[int]:
        return self.data["last_frame"]

    def record_frame(self, job: Any, record: Dict[str, Any], kept: Optional[Path]) -> None:
        """Frame ``job.frame`` is written: its ``record`` (size, SHA-256, inputs), the checkpoint
        ``kept`` for it (None: none kept), and this session's count, time and solver figures
        (``job.pressure``)."""
        frame = job.frame
        self.data["frame_records"][str(frame)] = record
        if kept is not None:
            self.data["checkpoints"] = [c for c in self.data["checkpoints"] if c["frame"] != frame] + [
                {"frame": frame, "bytes": kept.stat().st_size}]
        self.data["frames_done"].append(frame)
        self.data["last_frame"] = frame
        self.data["complete"] = frame == self._scene.frame_end
        self.session["frames"] += 1
        self.session["seconds"] = time.perf_counter() - self._t0
        self.session["pressure"] = job.pressure

    def save(self) -> None:
        write_manifest(self.cache_dir, self.data)


# ---- checkpoint ----------------------------------------------------------------------------

def fingerprint_until(fingerprint: Dict[str, Any], frame: int) -> Dict[str, Any]:
    """The fingerprint as the state after ``frame`` depends on it: the probe's and a mesh
    source's keys up to the first one at or after that frame (the poses up to ``frame`` are
    interpolated towards it), so that raising the end frame (more keys) still resumes the
    checkpoint."""
    out = dict(fingerprint)
    for name in ("probe", "source"):
        part = fingerprint.get(name)
        if part and "keys" in part:
            keys = sorted(part["keys"], key=lambda k: k[0])
            upto = next((i for i, k in enumerate(keys) if k[0] >= frame), len(keys) - 1)
            out[name] = {**part, "keys": keys[:upto + 1]}
    return out


def without_keys(fingerprint: Dict[str, Any]) -> Dict[str, Any]:
    """The fingerprint without the probe's and source's keyed poses: the global settings."""
    out = dict(fingerprint)
    for name in ("probe", "source"):
        part = out.get(name)
        if part and "keys" in part:
            out[name] = {k: v for k, v in part.items() if k != "keys"}
    return out


def settings_differences(saved: Dict[str, Any], now: Dict[str, Any]) -> List[str]:
    """Names of the fingerprint entries that differ (one level into dicts: 'fluid.vorticity')."""
    out = []
    for key in sorted(set(saved) | set(now)):
        a, b = saved.get(key), now.get(key)
        if a == b:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            out += [f"{key}.{k}" for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
        else:
            out.append(key)
    return out


def settings_digest(fingerprint: Dict[str, Any]) -> str:
    return hashlib.sha256(json.dumps(fingerprint, sort_keys=True).encode()).hexdigest()


def _memory_order(a: np.ndarray) -> str:
    """'F' for a Fortran-ordered array (as Simulation.state() returns), else 'C'."""
    return "F" if a.flags.f_contiguous and not a.flags.c_contiguous else "C"


def _memory_bytes(a: np.ndarray) -> memoryview:
    """The array's bytes in its own memory order, without a copy (a C-order copy only for an
    array that is neither C- nor Fortran-contiguous)."""
    view = a.T if _memory_order(a) == "F" else np.ascontiguousarray(a)
    return memoryview(view).cast("B")


def _array_digest(a: np.ndarray, order: str) -> str:
    """SHA-256 of the array's bytes as checkpoint formats 1 and 2 recorded it: in C order (format 1),
    or as stored in the .npy member, in the array's memory order (format 2: 'F' or 'C')."""
    if order == "C1":
        return hashlib.sha256(np.ascontiguousarray(a)).hexdigest()
    return hashlib.sha256(_memory_bytes(a)).hexdigest()


_CHUNK_BYTES = 1 << 22  # written in 4 MiB slices of the array's own memory


def save_checkpoint(cache_dir: "str | os.PathLike", frame: int, state: Dict[str, Any],
                    fingerprint: Dict[str, Any], inputs_sha256: Optional[str] = None) -> Path:
    """Write the state after ``frame`` (a dict from Simulation.state()) atomically as the
    latest checkpoint. ``inputs_sha256``: the digest of the global settings and every frame's
    inputs up to ``frame`` (plan.InputsLedger.chain), which load_checkpoint compares.

    Each array goes into the .npy member straight from its own memory (no copy); the zip records
    each member's CRC-32 as it is written, and reading the member back checks it, so the file
    carries no other digest of the arrays (a SHA-256 beside the CRC cost 13 ms of the writer's CPU
    a frame at 100x100x70 and found nothing the CRC misses: damage, not forgery, is what it is
    for). The metadata is the last member."""
    arrays = {k: v for k, v in state.items() if isinstance(v, np.ndarray)}
    scalars = {k: v for k, v in state.items() if not isinstance(v, np.ndarray)}
    if "meta" in arrays:
        raise ValueError("a state array may not be called 'meta' (the checkpoint's metadata member)")
    def write(f: Any) -> None:
        # np.savez's layout (uncompressed zip of .npy members, zip64), written by hand so that
        # the zip is closed on an error too (np.savez leaves it open when a write fails, and its
        # finaliser later seeks the file atomic_write has closed: "seek of closed file").
        with zipfile.ZipFile(f, mode="w", compression=zipfile.ZIP_STORED, allowZip64=True) as z:
            for name, a in arrays.items():
                _write_npy_member(z, name, a)
            meta = {
                "format": CHECKPOINT_FORMAT,
                "frame": int(frame),
                "scalars": {k: (float(v) if isinstance(v, float) else int(v)) for k, v in scalars.items()},
                "settings_sha256": settings_digest(fingerprint_until(fingerprint, frame)),
                # to say which setting differs on resume: without the keys when the inputs digest
                # covers them (a long performance's keys would make the metadata megabytes long)
                "settings": fingerprint_until(fingerprint, frame) if inputs_sha256 is None else without_keys(fingerprint),
                **({"inputs_sha256": inputs_sha256} if inputs_sha256 is not None else {}),
                "arrays": {k: {"order": _memory_order(a), "shape": list(a.shape), "dtype": str(a.dtype)}
                           for k, a in arrays.items()},
            }
            _write_npy_member(z, "meta", np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8))

    path = checkpoint_path(cache_dir)
    atomic_write(path, write, binary=True)
    return path


def _write_npy_member(z: zipfile.ZipFile, name: str, a: np.ndarray) -> None:
    """Write ``a`` as ``name``.npy into the zip from its own memory (zipfile adds its CRC-32)."""
    data = _memory_bytes(a)
    with z.open(name + ".npy", "w", force_zip64=True) as member:
        np.lib.format.write_array_header_2_0(member, np.lib.format.header_data_from_array_1_0(a))
        for start in range(0, len(data), _CHUNK_BYTES):
            member.write(data[start:start + _CHUNK_BYTES])


def load_checkpoint(cache_dir: "str | os.PathLike", fingerprint: Dict[str, Any],
                    inputs_sha256: Optional[Callable[[int], str]] = None,
                    path: "Optional[str | os.PathLike]" = None) -> Tuple[int, Dict[str, Any]]:
    """(frame, state dict for Simulation.set_state) of the cache's latest checkpoint, or of the
    checkpoint file ``path``; BakeError if it is missing, damaged, or was written for other
    settings. ``inputs_sha256(frame)``: where the checkpoint records the digest of the inputs
    up to its frame, it must equal this (the keys are then compared exactly, frame by frame)."""
    path = checkpoint_path(cache_dir) if path is None else Path(path)
    if not path.exists():
        raise BakeError(f"no checkpoint to resume from in '{Path(cache_dir)}' (expected {path}); bake without "
                        "resume to start from the first frame")
    fix = ("a resume (--resume) falls back to an earlier checkpoint or the first frame by itself; or free the "
           "cache and bake from the start")
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:  # our handle: closed on errors too
            meta = json.loads(bytes(z["meta"]).decode())
            arrays = {k: z[k] for k in meta["arrays"]}
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, EOFError, UnicodeDecodeError, TypeError) as exc:
        raise BakeError(f"checkpoint '{path}' is damaged or incomplete ({type(exc).__name__}: {exc}); {fix}") from None
    if meta.get("format") not in READABLE_CHECKPOINT_FORMATS:
        raise BakeError(f"checkpoint '{path}' has format {meta.get('format')!r}, this version reads "
                        f"{', '.join(map(str, READABLE_CHECKPOINT_FORMATS))}; {fix}")
    now = fingerprint_until(fingerprint, int(meta.get("frame", 0)))
    if inputs_sha256 is not None and "inputs_sha256" in meta:
        settings_match = meta["inputs_sha256"] == inputs_sha256(int(meta.get("frame", 0)))
        now = without_keys(fingerprint)
    else:
        settings_match = meta.get("settings_sha256") in (settings_digest(now), settings_digest(fingerprint))
    if not settings_match:
        saved = meta.get("settings")
        which = (", ".join(settings_differences(saved, now)) if isinstance(saved, dict)
                 else "resolution, fluid, probe keys, frames, grids or substeps") or "probe or source keys"
        raise BakeError(f"set these back to what the checkpoint was baked with, or bake from the start: checkpoint "
                        f"'{path}' was baked with other settings ({which} differ)")
    state: Dict[str, Any] = {}
    for k, info in meta["arrays"].items():
        a = arrays[k]
        order = "C1" if meta["format"] == 1 else info.get("order", "C")
        digest_differs = meta["format"] < 3 and _array_digest(a, order) != info.get("sha256")  # 3: the CRC
        if list(a.shape) != info["shape"] or str(a.dtype) != info["dtype"] or digest_differs:
            raise BakeError(f"checkpoint '{path}': array '{k}' does not match its checksum (the file is "
                            f"damaged); {fix}")
        state[k] = np.asfortranarray(a) if info.get("fortran") else a  # format 1 stored C order
    state.update(meta["scalars"])
    return int(meta["frame"]), state
