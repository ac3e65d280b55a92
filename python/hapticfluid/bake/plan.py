# SPDX-License-Identifier: GPL-3.0-or-later
"""Which frames of a cache still hold what the scene would bake now, and where a re-bake starts.

The bake records, per frame, what the frame consumed beyond the global settings (the keys the
probe's and a mesh source's poses in that frame are interpolated from: BakeScene.frame_inputs)
and, once, a digest of the global settings (everything else the frames depend on:
BakeScene.global_fingerprint). Each checkpoint records the digest of the global settings and of
every frame's inputs up to its frame (InputsLedger.chain).

So when the scene changes, the first frame whose inputs differ is known without simulating
anything, every frame before it is still exactly what a bake of the changed scene would write,
and the latest kept checkpoint before it is a state that bake would pass through: the re-bake
starts there, replays up to that first frame without writing, and writes from it on. A change
of a global setting (resolution, fluid, grids, ...) changes every frame: it re-bakes them all.
The same holds for frames that are missing or damaged (verify.py), and for frames beyond the
last one baked (an extended range, or a bake that stopped).
"""

from __future__ import annotations

import hashlib
import json
import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

from hapticfluid.bake import cache as _cache
from hapticfluid.bake import verify as _verify
from hapticfluid.bake.scene import BakeScene

log = logging.getLogger(__name__)

INPUTS_VERSION = 1  # how frame inputs and the global digest are computed (manifest "inputs.version")


class InputsLedger:
    """The scene's global digest and each frame's inputs, with the chained digest a checkpoint
    after frame f records: SHA-256 of the global digest and the inputs of frames start..f."""

    def __init__(self, scene: BakeScene):
        self.scene = scene
        self.global_settings = scene.global_fingerprint()
        self.global_sha256 = _cache.settings_digest(self.global_settings)
        self.frames: Dict[int, Dict[str, str]] = {
            f: scene.frame_inputs(f) for f in range(scene.frame_start, scene.frame_end + 1)}
        self._chain: Dict[int, str] = {}
        h = hashlib.sha256(self.global_sha256.encode())
        self._chain[scene.frame_start - 1] = h.hexdigest()
        for f in range(scene.frame_start, scene.frame_end + 1):
            h.update(json.dumps(self.frames[f], sort_keys=True).encode())
            self._chain[f] = h.hexdigest()

    def chain(self, frame: int) -> str:
        """The digest a checkpoint after ``frame`` must hold ('' for frames outside the scene)."""
        return self._chain.get(frame, "")

    def manifest_entry(self) -> Dict[str, Any]:
        return {"version": INPUTS_VERSION, "global_sha256": self.global_sha256, "global": self.global_settings}


@dataclass(frozen=True)
class RebakePlan:
    """What a bake of the scene into its cache does now (rebake_plan)."""

    kind: str  # fresh | settings | inputs | damaged | continue | complete | legacy
    frame_start: int
    frame_end: int
    first_frame: Optional[int]  # first frame to write; None: every frame is baked and up to date
    checkpoint_frame: int  # the state the bake starts from: a checkpoint's frame, or frame_start - 1 (rest)
    text: str  # one line for the panel and the log
    changed: Tuple[str, ...] = ()  # kind "settings": the settings that differ; "inputs": probe / source
    damaged: Dict[int, str] = field(default_factory=dict)  # frame -> what is wrong with its file
    checkpoints: Tuple[int, ...] = ()  # the usable checkpoints' frames (kept and latest), ascending

    @property
    def valid_frames(self) -> range:
        """The frames kept as they are (every frame of the range when there is nothing to do)."""
        return range(self.frame_start, (self.frame_end + 1) if self.first_frame is None else self.first_frame)

    @property
    def from_rest(self) -> bool:
        return self.checkpoint_frame < self.frame_start

    @property
    def keeps_frames(self) -> bool:
        """Whether the frames before first_frame stay (a fresh bake and a changed setting keep none:
        the cache's earlier bake is freed)."""
        return self.kind not in ("fresh", "settings")

    @property
    def last_kept_frame(self) -> Optional[int]:
        """The last frame kept as it is before the first frame to write (None: none is kept)."""
        if self.first_frame is None:
            return self.frame_end
        return self.first_frame - 1 if self.keeps_frames and self.first_frame > self.frame_start else None


def _span(a: int, b: int) -> str:
    return f"{a}" if a == b else f"{a}-{b}"


def _from(checkpoint: int, start: int) -> str:
    return "from the start" if checkpoint < start else f"from the checkpoint at {checkpoint}"


def rebake_plan(scene: BakeScene, check_files: bool = True, ledger: Optional[InputsLedger] = None,
                resume: bool = True) -> RebakePlan:
    """Compare the cache's manifest with ``scene`` and say what a bake (resume) does.

    check_files: read every frame file the plan would keep and compare its size and SHA-256
        with the manifest's record (as resume does before it trusts them); False checks that
        each exists with its recorded size only (cheap enough for a panel).
    resume: False says what a bake that starts over does: every frame, from rest (kind "fresh").
    Raises BakeError when the folder holds frames no hapticfluid bake wrote."""
    start, end = scene.frame_start, scene.frame_end
    cache_dir = Path(scene.cache_dir)
    if not resume:
        _cache.check_frames_are_ours(cache_dir)  # never start work that would then free others' frames
        return RebakePlan("fresh", start, end, start, start - 1, f"bake every frame, {start}-{end}, from the start")
    ledger = ledger or InputsLedger(scene)
    if not cache_dir.is_dir():
        return RebakePlan("fresh", start, end, start, start - 1, f"nothing baked yet: bake {_span(start, end)}")
    _cache.check_frames_are_ours(cache_dir)
    try:
        manifest = _cache.read_manifest(cache_dir)
    except _cache.BakeError as exc:
        log.warning("%s", exc)
        manifest = None
    if manifest is None:
        return _legacy_plan(scene, cache_dir, None, check_files, ledger)
    inputs = manifest.get("inputs")
    if not isinstance(inputs, dict) or inputs.get("version") != INPUTS_VERSION:
        return _legacy_plan(scene, cache_dir, manifest, check_files, ledger)

    if inputs.get("global_sha256") != ledger.global_sha256:
        saved = inputs.get("global")
        changed = tuple(_cache.settings_differences(saved, ledger.global_settings)) if isinstance(saved, dict) else ()
        what = ", ".join(changed) if changed else "the scene's settings"
        return RebakePlan("settings", start, end, start, start - 1,
                          f"{what} changed: re-bake every frame, {_span(start, end)}", changed=changed)

    records = _cache.manifest_records(manifest)
    done = set(_verify.claimed_frames(manifest))
    first_changed, changed_what = None, ()
    first_missing = None
    for f in range(start, end + 1):
        record = records.get(f)
        if f not in done or record is None:
            first_missing = f
            break
        saved = record.get("inputs")
        if saved != ledger.frames[f]:
            first_changed = f
            parts = set(saved or {}) | set(ledger.frames[f])
            changed_what = tuple(sorted(p for p in parts if (saved or {}).get(p) != ledger.frames[f].get(p)))
            break
    limit = first_changed if first_changed is not None else first_missing if first_missing is not None else end + 1
    damaged = _damaged_frames(cache_dir, range(start, limit), records, check_files)
    first_damaged = min(damaged) if damaged else None
    first = min(f for f in (first_changed, first_missing, first_damaged, end + 1) if f is not None)
    checkpoints = usable_checkpoints(cache_dir, first)
    if first > end:
        return RebakePlan("complete", start, end, None, end, f"frames {_span(start, end)} are baked and up to date",
                          checkpoints=checkpoints)
    checkpoint = checkpoints[-1] if checkpoints else start - 1
    todo = f"{_span(first, end)} {_from(checkpoint, start)}"
    if first == first_damaged:
        problem = damaged[first]
        return RebakePlan("damaged", start, end, first, checkpoint,
                          f"frame {first} is {problem}: re-bake {todo}", damaged=damaged, checkpoints=checkpoints)
    if first == first_changed:
        who = " and ".join(changed_what) or "probe"
        return RebakePlan("inputs", start, end, first, checkpoint,
                          f"{who} keys changed from frame {first}: re-bake {todo}", changed=changed_what,
                          checkpoints=checkpoints)
    if first == start:
        return RebakePlan("fresh", start, end, first, checkpoint, f"nothing baked yet: bake {todo}",
                          checkpoints=checkpoints)
    return RebakePlan("continue", start, end, first, checkpoint,
                      f"frames {_span(start, first - 1)} baked: bake {todo}", checkpoints=checkpoints)


def _damaged_frames(cache_dir: Path, frames: range, records: Dict[int, Dict[str, Any]],
                    check_files: bool) -> Dict[int, str]:
    return dict(_verify.verify_frames(cache_dir, frames, records, read=check_files).damaged)


def usable_checkpoints(cache_dir: Path, before: int) -> Tuple[int, ...]:
    """Frames of the checkpoints (kept ones and the latest) that hold a state before frame
    ``before``, ascending. Their contents are checked when one is loaded (load_checkpoint)."""
    frames = set(f for f in _cache.list_kept_checkpoints(cache_dir) if f < before)
    latest = _cache.checkpoint_frame(_cache.checkpoint_path(cache_dir))
    if latest is not None and latest < before:
        frames.add(latest)
    return tuple(sorted(frames))


def checkpoint_file(cache_dir: Path, frame: int) -> Path:
    """The file holding the checkpoint of ``frame``: the kept one, else the latest."""
    kept = _cache.kept_checkpoint_path(cache_dir, frame)
    return kept if kept.is_file() else _cache.checkpoint_path(cache_dir)


def _legacy_plan(scene: BakeScene, cache_dir: Path, manifest: Optional[Dict[str, Any]], check_files: bool,
                 ledger: InputsLedger) -> RebakePlan:
    """A cache from before per-frame inputs were recorded (or without a readable manifest):
    continue after its latest checkpoint when that checkpoint matches the scene (load_checkpoint
    compares the settings), re-checking the frames before it."""
    start, end = scene.frame_start, scene.frame_end
    latest = _cache.checkpoint_frame(_cache.checkpoint_path(cache_dir))
    if latest is None:
        if _cache.list_frames(cache_dir):
            return RebakePlan("settings", start, end, start, start - 1,
                              f"the cache has no usable checkpoint: re-bake every frame, {_span(start, end)}")
        return RebakePlan("fresh", start, end, start, start - 1, f"nothing baked yet: bake {_span(start, end)}")
    latest = min(latest, end)
    damaged = _damaged_frames(cache_dir, range(start, latest + 1), _cache.manifest_records(manifest), check_files)
    if damaged:
        first = min(damaged)
        return RebakePlan("damaged", start, end, first, start - 1,
                          f"frame {first} is {damaged[first]}: re-bake {_span(first, end)} from the start",
                          damaged=damaged)
    if latest >= end:
        return RebakePlan("complete", start, end, None, end, f"frames {_span(start, end)} are baked and up to date")
    return RebakePlan("legacy", start, end, latest + 1, latest,
                      f"frames {_span(start, latest)} baked: bake {_span(latest + 1, end)} from the checkpoint at "
                      f"{latest}", checkpoints=(latest,))


def describe_checkpoints(scene: BakeScene) -> str:
    """'6.34 MB each, 12 kept' for the scene's resolution, range and interval."""
    return checkpoint_cost(scene.grid_resolution, scene.frame_count, scene.checkpoint_every)


def checkpoint_cost(cells: Tuple[int, int, int], frame_count: int, every: int) -> str:
    """'6.34 MB each, 12 kept' (and the total from 1 GB on) for a grid of ``cells``, a bake of
    ``frame_count`` frames and a checkpoint kept every ``every`` frames (0: none kept)."""
    size = _cache.checkpoint_bytes(cells)
    kept = max(0, frame_count) // every if every else 0
    return f"{_bytes(size)} each, {kept} kept" + (f" ({_bytes(kept * size)})" if kept * size >= 1e9 else "")


def _bytes(n: float) -> str:
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("KB", 1e3)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n:.0f} bytes"


def frame_states(scene: BakeScene, plan: RebakePlan) -> List[Tuple[int, int, str]]:
    """(first, last, state) runs over the scene's frames for the Timeline bar: 'baked' for the
    frames kept, 'outdated' for baked frames the plan re-bakes, 'missing' for the rest."""
    runs: List[Tuple[int, int, str]] = []
    baked = set(_cache.list_frames(scene.cache_dir))
    for f in range(plan.frame_start, plan.frame_end + 1):
        state = "baked" if f in plan.valid_frames else ("outdated" if f in baked else "missing")
        if runs and runs[-1][2] == state and runs[-1][1] == f - 1:
            runs[-1] = (runs[-1][0], f, state)
        else:
            runs.append((f, f, state))
    return runs


def verify_checkpoints(scene: BakeScene, ledger: Optional[InputsLedger] = None) -> Dict[str, str]:
    """Check every checkpoint file of the cache (kept ones and the latest): each array against
    its SHA-256, and the settings and inputs it was baked with against ``scene``. Returns
    {file name: what is wrong} for the ones that fail ({} when all are sound)."""
    ledger = ledger or InputsLedger(scene)
    cache_dir = Path(scene.cache_dir)
    files = [_cache.kept_checkpoint_path(cache_dir, f) for f in _cache.list_kept_checkpoints(cache_dir)]
    if _cache.checkpoint_path(cache_dir).is_file():
        files.append(_cache.checkpoint_path(cache_dir))
    problems = {}
    fingerprint = scene.fingerprint()
    for path in files:
        try:
            _cache.load_checkpoint(cache_dir, fingerprint, inputs_sha256=ledger.chain, path=path)
        except _cache.BakeError as exc:
            problems[f"{_cache.CHECKPOINT_DIR}/{path.name}"] = str(exc)
    return problems
