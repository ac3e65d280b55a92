# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid bake SCENE.json [--resume] [--resolution N] ...``.

Bakes the scene (format: :mod:`hapticfluid.bake.scene`) into its cache folder and prints one
line per frame with an ETA. Ctrl-C (SIGINT) or SIGTERM cancels between substeps, keeping every
complete frame and the checkpoint; run again with ``--resume`` to continue.
"""

from __future__ import annotations

import argparse
import signal
import sys
import itertools
from pathlib import Path

import hapticfluid as hf
from hapticfluid.bake import cache as _cache
from hapticfluid.bake import plan as _plan
from hapticfluid.bake import verify as _verify
from hapticfluid.bake.driver import BakeProgress, bake
from hapticfluid.bake.scene import load_scene

# True when this process is ``python3 -m hapticfluid`` (set by hapticfluid/__main__.py): the bake
# command then ignores SIGINT/SIGTERM once the bake is over, for the rest of the process (see
# cmd_bake). Called in-process (tests, scripts), it restores the previous handlers instead.
RUN_AS_PROGRAM = False


def add_parser(sub, resolution_type) -> None:
    p = sub.add_parser(
        "bake",
        help="bake a scene (probe trajectory + fluid settings) to an OpenVDB frame sequence",
        description="Simulate the scene described by SCENE (JSON: domain, resolution, fluid, source, "
                    "probe keys, frames, substeps, cache; see hapticfluid.bake.scene) and write "
                    "<cache>/data/fluid_data_####.vdb per frame, a checkpoint and a manifest. "
                    "Ctrl-C stops between substeps; --resume continues after the last complete frame.")
    p.add_argument("scene", metavar="SCENE", help="scene description (.json)")
    p.add_argument("--resume", action="store_true",
                   help="bake only what the cache lacks: keep every frame that still holds what the scene bakes and "
                        "re-bake from the first missing, damaged or changed one (changed probe or source keys), "
                        "starting at the latest checkpoint before it; a changed setting (resolution, fluid) "
                        "re-bakes all, as does an empty cache")
    p.add_argument("--until", type=int, default=None, metavar="FRAME",
                   help="stop after this frame (within the scene's frames), keeping its checkpoint: the next "
                        "'--resume' continues from it (farm chunks)")
    p.add_argument("--plan", action="store_true",
                   help="bake nothing: say what '--resume' would do (which frames are kept, which re-baked and "
                        "from which checkpoint) and the checkpoints' disk cost")
    p.add_argument("--resolution", type=resolution_type, default=None, metavar="N",
                   help="cells along the domain's longest edge (overrides the scene's 'resolution')")
    p.add_argument("--cache", default=None, metavar="DIR",
                   help="cache folder (overrides the scene's cache.directory)")
    p.add_argument("--verify", action="store_true",
                   help="bake nothing: check every frame file the cache's manifest claims (size and SHA-256 "
                        "the bake recorded) and list the missing or damaged ones; exit 0 if all are sound, "
                        "1 if not (--resume rebakes them)")
    p.add_argument("--backend", choices=hf.BACKENDS, default=None,
                   help="where the simulation computes (overrides the scene's \"backend\"): auto (a hardware GPU "
                        "if one gives a context, else the CPU backend), gpu (OpenGL, llvmpipe included) or cpu; "
                        "default: the scene's, else HAPTICFLUID_BACKEND, else auto")
    p.add_argument("--quiet", action="store_true", help="print only errors and the summary")
    p.set_defaults(func=cmd_bake)


class _SignalStop:
    """What Ctrl-C (SIGINT) and SIGTERM ask of a bake: the first, stop after this substep; the
    second, stop at once (the frames still queued for the writer are dropped; the one being
    written lands whole); later ones, nothing more. The bake reads cancelled() and now() where
    it waits (bake.driver), so the handler only counts: it takes no lock and raises nothing. A
    handler runs between two bytecodes of the main thread, wherever they are, and a second
    signal can run it again inside the first: a threading.Event's set() there deadlocked on its
    own lock (two SIGINTs at once), and a KeyboardInterrupt raised there can leave a queue's lock
    held. next() on the counter is one C call, so two nested handlers still get 0 and 1."""

    def __init__(self) -> None:
        self._signals = itertools.count()
        self._after_substep = False  # each flag is written by one handler call alone
        self._at_once = False
        self.over = False  # the bake has returned or raised: a signal now changes nothing

    def on_signal(self, signum, _frame) -> None:
        if self.over:
            return
        n = next(self._signals)
        if n == 0:
            self._after_substep = True
            print(f"\nbake: {signal.Signals(signum).name}: stopping after this substep "
                  "(again to stop at once)", file=sys.stderr, flush=True)
        elif n == 1:
            self._at_once = True  # no print: it could land inside the first one's (a reentrant write)

    def cancelled(self) -> bool:
        return self._after_substep or self._at_once

    def now(self) -> bool:
        return self._at_once


def cmd_bake(args: argparse.Namespace) -> int:
    scene = load_scene(args.scene)
    if args.resolution is not None:
        scene = scene.with_resolution(args.resolution)
    if args.cache is not None:
        from dataclasses import replace
        scene = replace(scene, cache_dir=Path(args.cache))
    if args.backend is not None:
        from dataclasses import replace
        scene = replace(scene, backend=args.backend)
    if args.verify:
        return verify_command(scene, args)
    if args.plan:
        return plan_command(scene)

    stop = _SignalStop()
    previous = {s: signal.signal(s, stop.on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    last_len = [0]

    def show(p: BakeProgress) -> None:
        if args.quiet or not sys.stdout.isatty():
            return
        line = f"  {p.text()}"
        print("\r" + line.ljust(last_len[0]), end="", flush=True)
        last_len[0] = len(line)

    def log(line: str) -> None:
        if not args.quiet:
            if last_len[0]:
                print("\r" + " " * last_len[0] + "\r", end="")
                last_len[0] = 0
            print(line, flush=True)

    try:
        result = bake(scene, resume=args.resume, progress=show, cancel=stop.cancelled, log=log, until=args.until,
                      stop_now=stop.now)
    finally:
        stop.over = True
        for s, handler in previous.items():
            # A program only prints its summary and exits from here. Python's own handler (back
            # in place) would raise KeyboardInterrupt where nothing catches it, and interpreter
            # teardown resets SIGINT to its default: either way a late Ctrl-C (the second of two
            # quick ones) killed the process by the signal (exit -2) instead of exit 130.
            signal.signal(s, signal.SIG_IGN if RUN_AS_PROGRAM else handler)
    frames = _cache.list_frames(result.cache_dir)
    print(f"bake {result.status}: {result.frames_written} frame(s) in {result.seconds:.1f} s"
          + (f" ({result.seconds_per_frame:.2f} s/frame)" if result.frames_written else "")
          + f"; cache {result.cache_dir} holds {len(frames)} frame file(s)"
          + (f", last complete frame {result.last_frame}" if result.last_frame is not None else ""))
    if result.damaged_frames:
        print(f"rebaked missing or damaged frame(s) {', '.join(map(str, result.damaged_frames))}")
    if result.status == "cancelled":
        print(f"resume with: {resume_command(args)}")
        return 130
    return 0


def verify_command(scene, args: argparse.Namespace) -> int:
    """``bake --verify``: report the cache's damaged frames and checkpoints; 0 if none, 1 otherwise."""
    cache_dir = scene.cache_dir
    if not Path(cache_dir).is_dir():
        raise _cache.BakeError(f"cache folder '{cache_dir}' does not exist: there is no bake to verify")
    with _cache.bake_lock(cache_dir):  # not while a bake rewrites the frames
        report = _verify.verify_cache(cache_dir)
        checkpoints = _plan.verify_checkpoints(scene)
    for line in report.lines():
        print(line)
    for name, problem in sorted(checkpoints.items()):
        print(f"{name}: {problem}")
    unrecorded = len(report.checked) - report.recorded
    how = f" ({unrecorded} without a recorded digest: header checked only)" if unrecorded else ""
    kept = len(_cache.list_kept_checkpoints(cache_dir)) + _cache.checkpoint_path(cache_dir).is_file()
    if report.ok and not checkpoints:
        print(f"verify: all {len(report.checked)} frame file(s) the manifest lists are sound{how}, and all "
              f"{kept} checkpoint(s)")
        return 0
    print(f"verify: {len(report.damaged)} of {len(report.checked)} frame file(s) are missing or damaged{how}, "
          f"{len(checkpoints)} of {kept} checkpoint(s) unusable; rebake with: {resume_command(args)}")
    return 1


def plan_command(scene) -> int:
    """``bake --plan``: print what a resume would do; 0 when there is nothing to bake, 1 otherwise."""
    plan = _plan.rebake_plan(scene, check_files=True)
    print(plan.text)
    for f in sorted(plan.damaged):
        print(f"frame {f}: {plan.damaged[f]}")
    kept = _cache.list_kept_checkpoints(scene.cache_dir)
    print(f"checkpoints: every {scene.checkpoint_every} frame(s), {_plan.describe_checkpoints(scene)}"
          + (f"; kept now: {', '.join(map(str, kept))}" if kept else ""))
    return 0 if plan.first_frame is None else 1


def resume_command(args: argparse.Namespace) -> str:
    """The command line that resumes this bake: the same scene, resolution and cache folder (a
    hint without --cache would resume, or fail to find, the scene's own cache instead)."""
    import shlex

    words = ["python3", "-m", "hapticfluid", "bake", str(args.scene), "--resume"]
    if getattr(args, "until", None) is not None:
        words += ["--until", str(args.until)]
    if args.resolution is not None:
        words += ["--resolution", str(args.resolution)]
    if args.cache is not None:
        words += ["--cache", str(Path(args.cache).absolute())]
    if getattr(args, "backend", None) is not None:
        words += ["--backend", args.backend]
    return " ".join(shlex.quote(w) for w in words)
