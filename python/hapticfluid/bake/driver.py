# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake loop: steps a Simulation along the probe's trajectory and writes one VDB per frame.

Deterministic: the same scene gives bit-identical frames, whether baked in one go or stopped
(cancel, crash, SIGKILL) and resumed, because every frame's inputs (probe motion per substep,
substep count) are functions of the scene and the state after the previous frame, and that
state is checkpointed exactly after each frame.

Order of writes per frame f: the frame file (atomic), then the checkpoint for f (atomic), then
the manifest (with f's size and SHA-256). A kill between them loses at most frame f: resume
restarts from the checkpoint and rewrites f identically. These writes run on a writer thread
(writer.py) while the simulation steps frame f+1, frames in order, at most two in flight; a kill
then loses at most those two, and resume rewrites them identically. A failed write stops the
bake with a BakeError naming the frame, after every earlier frame has landed.

Resume bakes what the cache lacks (plan.py): it finds the first frame that is missing, damaged
(verify.py) or whose inputs changed, starts from the latest checkpoint before it (kept every
scene.checkpoint_every frames, beside the latest), replays the frames between without writing
them (they are sound, and the replay reproduces them bit for bit) and rewrites every frame from
it on. Each frame's record in the manifest carries the inputs it consumed, and each checkpoint
the digest of the inputs up to its frame, so a checkpoint is only used for the scene that made it.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

import hapticfluid as hf
from hapticfluid import assembly
from hapticfluid.bake import cache as _cache
from hapticfluid.bake import plan as _plan
from hapticfluid.bake import verify as _verify
from hapticfluid.bake import writer as _writer
from hapticfluid.bake.scene import BakeScene, ProbeSpec, SmokeSource
from hapticfluid.bake.trajectory import Motion

CancelCheck = Union[threading.Event, Callable[[], bool], None]

_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class BakeProgress:
    """What a progress callback receives (after every substep and every finished frame)."""

    frame: int  # the frame being baked (or just finished)
    frame_start: int
    frame_end: int
    frames_done: int  # complete frames in the cache (including earlier sessions)
    substep: int  # substeps done in this frame
    substeps: int  # substeps this frame takes
    elapsed_s: float  # wall time of this session
    eta_s: float  # estimated wall time left (nan until a frame has finished)
    frame_finished: bool  # True on the call that follows writing `frame`

    @property
    def fraction(self) -> float:
        total = self.frame_end - self.frame_start + 1
        partial = self.substep / self.substeps if self.substeps and not self.frame_finished else 0.0
        return min(1.0, (self.frames_done + partial) / total)

    def text(self) -> str:
        eta = "" if math.isnan(self.eta_s) else f", {self.eta_s:.0f} s left"
        return (f"frame {self.frame} ({self.frames_done}/{self.frame_end - self.frame_start + 1} done, "
                f"substep {self.substep}/{self.substeps}{eta})")


@dataclass(frozen=True)
class BakeResult:
    status: str  # "finished" or "cancelled"
    cache_dir: Path
    frames_written: int  # in this session
    last_frame: Optional[int]  # last complete frame in the cache
    resumed_from: Optional[int]  # checkpoint frame this session started after
    seconds: float  # wall time of this session
    seconds_per_frame: float  # mean over this session's frames (nan if none)
    damaged_frames: Tuple[int, ...] = ()  # resume: frames found missing or damaged, and rebaked
    plan: Optional["_plan.RebakePlan"] = None  # what the bake set out to do (plan.rebake_plan)


def apply_probe(sim: "hf.Simulation", probe: ProbeSpec, motion: Motion) -> None:
    """Put the probe where the trajectory says for one substep (assembly.place_probe: a sphere
    placed whole, its radius following the transform's scale; a mesh uploaded once, then only moved)."""
    assembly.place_probe(sim, assembly.Probe(probe.shape, motion.pose.matrix(), radius=probe.radius,
                                             vertices=probe.vertices, triangles=probe.triangles,
                                             velocity=motion.velocity, angular_velocity=motion.angular_velocity))


def _apply_substep_probe(sim: "hf.Simulation", probe: ProbeSpec, frame: int, s: int, n: int, dt: float) -> None:
    """apply_probe for substep s (0-based) of n in ``frame``: the trajectory's motion over that
    substep's share of the frame. The trajectory check and the stepping loop both come here, so
    they see the same poses."""
    a, b = (frame - 1) + s / n, (frame - 1) + (s + 1) / n
    apply_probe(sim, probe, probe.trajectory.motion(a, b, dt))


def source_at(source: SmokeSource, frame_time: float) -> "assembly.Source":
    """The smoke source where it is at ``frame_time`` (frames): a sphere stays put; a mesh is at
    its trajectory's pose."""
    matrix = None if source.shape == "sphere" else source.trajectory.pose(frame_time).matrix()
    return assembly.Source(source.shape, source.density, source.temperature, source.emission, centre=source.centre,
                           radius=source.radius, matrix=matrix, vertices=source.vertices, triangles=source.triangles)


def apply_source(sim: "hf.Simulation", source: SmokeSource, frame_time: float) -> None:
    """Put the smoke source where it is at ``frame_time`` (frames) (assembly.place_source: a
    sphere set once; a mesh uploaded once, then only moved)."""
    assembly.place_source(sim, source_at(source, frame_time))


def _apply_substep_source(sim: "hf.Simulation", source: SmokeSource, frame: int, s: int, n: int) -> None:
    """apply_source for substep s (0-based) of n in ``frame``: the pose at the substep's end, as
    the probe's (the step emits where the source is when it ends)."""
    apply_source(sim, source, (frame - 1) + (s + 1) / n)


def check_trajectory(sim: "hf.Simulation", scene: BakeScene, first: int,
                     cancelled: Callable[[], bool] = lambda: False) -> bool:
    """Before any step: hand the engine every substep pose of frames first..end (fixed substeps;
    max_substeps per frame when adaptive) so its own checks (domain margin, mesh validity, speed)
    refuse a bad trajectory up front, naming the frame. Leaves no probe set. Checks ``cancelled``
    once per frame (a long trajectory takes a while): returns False if it was cancelled.
    A mesh smoke source's poses are checked the same way (the source stays set)."""
    n = scene.max_substeps if scene.substeps == "adaptive" else int(scene.substeps)
    source = scene.source
    if source is not None and source.shape == "mesh":
        for frame in range(first, scene.frame_end + 1):
            if cancelled():
                return False
            for s in range(n):
                try:
                    _apply_substep_source(sim, source, frame, s, n)
                except hf.InvalidArgumentError as exc:
                    raise hf.InvalidArgumentError(
                        f"the smoke source's path is refused at frame {frame} (substep {s + 1} of {n}): {exc}") from None
    if scene.probe is None:
        return True
    dt = scene.frame_dt / n
    try:
        for frame in range(first, scene.frame_end + 1):
            if cancelled():
                return False
            for s in range(n):
                try:
                    _apply_substep_probe(sim, scene.probe, frame, s, n, dt)
                except hf.InvalidArgumentError as exc:
                    raise hf.InvalidArgumentError(
                        f"the probe's trajectory is refused at frame {frame} (substep {s + 1} of {n}): {exc}") from None
    finally:
        sim.clear_probe()
    return True


def scene_description(scene: BakeScene) -> "assembly.SceneDescription":
    """What the bake's Simulation is made from (assembly.build): the scene's FluidSettings
    (assembly.fluid_settings) and its smoke source at the pose before the first frame (each
    substep moves a mesh source). No probe: each substep places it."""
    settings = assembly.fluid_settings(scene.domain_origin, scene.domain_size, scene.resolution, scene.fluid,
                                       backend=scene.backend, device=scene.device)
    source = None if scene.source is None else source_at(scene.source, scene.frame_start - 1)
    return assembly.SceneDescription(settings, source=source)


def make_simulation(scene: BakeScene) -> "hf.Simulation":
    """The scene's Simulation, made by assembly.build (no session)."""
    sim, _ = assembly.build(scene_description(scene))
    return sim


def _max_face_speed(sim: "hf.Simulation") -> float:
    return max(float(np.abs(c).max()) for c in sim.velocity())


def substeps_for_frame(scene: BakeScene, sim: "hf.Simulation", frame: int) -> int:
    """Fixed count, or the CFL count from the fastest face velocity now and the probe's speed
    over the frame (deterministic: both come from the scene and the restored state)."""
    if scene.substeps != "adaptive":
        return int(scene.substeps)
    speed = _max_face_speed(sim)
    if scene.probe is not None:
        m = scene.probe.trajectory.motion(frame - 1, frame, scene.frame_dt)
        speed = max(speed, float(np.linalg.norm(m.velocity)))
    n = math.ceil(speed * scene.frame_dt / (scene.cfl * scene.cell_size))
    return max(1, min(scene.max_substeps, n))


def frame_metadata(scene: BakeScene, frame: int, substeps: int) -> Dict[str, Any]:
    f = scene.fluid
    return {
        "creator": f"hapticfluid {hf.__version__}",
        "hapticfluid_version": hf.__version__,
        "frame": int(frame),
        "fps": float(scene.fps),
        "time_s": float((frame - scene.frame_start + 1) / scene.fps),
        "resolution": tuple(int(n) for n in scene.grid_resolution),
        "file_base_resolution": tuple(int(n) for n in scene.grid_resolution),  # Mantaflow's name
        "voxel_size": float(scene.cell_size),
        "domain_origin": tuple(float(x) for x in scene.domain_origin),
        "domain_size": tuple(float(x) for x in scene.grid_size),
        "substeps": int(substeps),
        "fluid_density": float(f["fluid_density"]),
        "gravity": tuple(float(x) for x in f["gravity"]),
        "open_top": bool(f["open_top"]),
        "advection": str(f["advection"]),
        "vorticity": float(f["vorticity"]),
        "heat_buoyancy": float(f["heat_buoyancy"]),
        "smoke_weight": float(f["smoke_weight"]),
        "smoke_dissipation": float(f["smoke_dissipation"]),
        "heat_dissipation": float(f["heat_dissipation"]),
        "pressure_iterations": int(f["pressure_iterations"]),
        "pressure_is_dynamic": True,
    }


def write_frame(scene: BakeScene, state: Dict[str, Any], frame: int, substeps: int) -> Path:
    """Write frame ``frame`` from ``state`` (a dict from Simulation.state(): its arrays are what
    density(), velocity() and pressure(hydrostatic=False) return, read once for the frame file
    and the checkpoint)."""
    path = _cache.frame_path(scene.cache_dir, frame)
    velocity = (state["velocity_x"], state["velocity_y"], state["velocity_z"])
    hf.write_vdb(str(path), state["density"], scene.cell_size, tuple(scene.domain_origin),
                 velocity=velocity if "velocity" in scene.grids else None,
                 pressure=state["pressure"] if "pressure" in scene.grids else None,
                 compression=scene.compression, half_float=scene.half_float, tolerance=scene.tolerance,
                 metadata=frame_metadata(scene, frame, substeps))
    return path


class _SolverTally:
    """What the pressure solves of a session reached, for the manifest: the worst relative
    residual (the solver's own estimate; tolerance mode only), the iterations, and how many
    steps stopped at the iteration cap above the tolerance."""

    def __init__(self) -> None:
        self.steps = 0
        self.iterations = 0
        self.max_iterations = 0
        self.unconverged = 0
        self.worst: Optional[float] = None

    def add(self, report: "hf.StepReport") -> None:
        self.steps += 1
        self.iterations += int(report.pressure_iterations)
        self.max_iterations = max(self.max_iterations, int(report.pressure_iterations))
        if not report.converged:
            self.unconverged += 1
        if report.relative_residual >= 0.0:  # -1: fixed iteration count, nothing measured
            self.worst = max(self.worst or 0.0, float(report.relative_residual))

    def record(self) -> Dict[str, Any]:
        return {"steps": self.steps, "mean_iterations": self.iterations / self.steps if self.steps else 0.0,
                "max_iterations": self.max_iterations, "unconverged_steps": self.unconverged,
                "max_relative_residual": self.worst}


def _cancel_check(cancel: CancelCheck) -> Callable[[], bool]:
    if cancel is None:
        return lambda: False
    if isinstance(cancel, threading.Event):
        return cancel.is_set
    return cancel


def bake(scene: BakeScene, resume: bool = False, progress: Optional[Callable[[BakeProgress], None]] = None,
         cancel: CancelCheck = None, log: Optional[Callable[[str], None]] = None,
         until: Optional[int] = None, stop_now: CancelCheck = None) -> BakeResult:
    """Bake ``scene`` into its cache folder.

    resume: bake only what the cache lacks (plan.rebake_plan): keep every frame that still holds
        what this scene bakes, and re-bake from the first frame that is missing, damaged (size and
        SHA-256 against the manifest) or whose inputs changed (the probe's or source's keys),
        starting from the latest kept checkpoint before it; a changed global setting (resolution,
        fluid, ...) re-bakes every frame, as does an empty cache. Otherwise the cache's previous
        bake files are deleted first and every frame is baked. BakeResult.plan says which case
        applied; BakeResult.damaged_frames lists the damaged frames found.
    progress: called after every substep and every written frame with a BakeProgress.
    cancel: a threading.Event or a callable; checked once per frame of the trajectory check and
        between substeps. A bake cancelled before its first step leaves the cache as it was (an
        earlier bake included); later, it keeps every complete frame and its checkpoint, so it
        can be resumed.
    log: receives one line per frame.
    until: stop after this frame (frame_start .. frame_end; default frame_end), keeping its
        checkpoint (a farm chunk: the next chunk resumes from it).
    stop_now: like cancel, and more: once it is set, the frames stepped but not yet written are
        dropped (the one being written lands whole, with its checkpoint); the bake stops at the
        next substep or while it waits for the writer (a second Ctrl-C: bake.command).
    Raises InvalidArgumentError (scene, until), BakeError (cache, checkpoint), HapticFluidError (engine).
    """
    say = log or (lambda _line: None)
    if until is not None and (isinstance(until, bool) or not isinstance(until, int)
                              or not scene.frame_start <= until <= scene.frame_end):
        raise hf.InvalidArgumentError(f"until must be a frame from {scene.frame_start} to {scene.frame_end} (the "
                                      f"scene's frames), got {until!r}")
    stops_now = _cancel_check(stop_now)
    cancels = _cancel_check(cancel)

    def is_cancelled() -> bool:
        return cancels() or stops_now()

    cache_dir = _cache.prepare_cache(scene.cache_dir)  # before any work: a clear error if unwritable
    with _cache.bake_lock(cache_dir):  # one bake per cache folder at a time (processes included)
        return _bake_locked(scene, cache_dir, resume, progress, _Stops(is_cancelled, stops_now), say,
                            scene.frame_end if until is None else until)


def _plan_for(scene: BakeScene, cache_dir: Path, resume: bool, ledger: _plan.InputsLedger,
              say: Callable[[str], None]) -> Tuple[_plan.RebakePlan, Optional[Dict[str, Any]]]:
    """What this bake does (plan.rebake_plan; resume: what the cache lacks, checking every frame
    it keeps) and the cache's manifest before it (resume only: the frames kept keep their records)."""
    if not resume:
        return _plan.rebake_plan(scene, resume=False), None
    _cache.remove_temporaries(cache_dir)
    plan = _plan.rebake_plan(scene, check_files=True, ledger=ledger)
    for f in sorted(plan.damaged):
        say(f"damaged: frame {f}: {plan.damaged[f]} ({_cache.FRAME_PREFIX}{f:04d}.vdb)")
    try:
        return plan, _cache.read_manifest(cache_dir)
    except _cache.BakeError as exc:  # resume needs only the checkpoint; the manifest is rewritten
        say(f"{exc}: resuming without it (every frame file is checked against its header)")
        _log.warning("%s", exc)
        return plan, None


def _start_state(scene: BakeScene, cache_dir: Path, plan: _plan.RebakePlan, ledger: _plan.InputsLedger,
                 say: Callable[[str], None]) -> Tuple[Optional[int], Optional[Dict[str, Any]]]:
    """(frame, state) of the latest usable checkpoint the plan allows, or (None, None) to start
    from rest. A checkpoint that fails its checks is reported and the one before it tried."""
    if not plan.keeps_frames or plan.from_rest:
        return None, None
    fingerprint = scene.fingerprint()
    for frame in reversed(plan.checkpoints):
        path = _plan.checkpoint_file(cache_dir, frame)
        try:
            at, state = _cache.load_checkpoint(cache_dir, fingerprint, inputs_sha256=ledger.chain, path=path)
        except _cache.BakeError as exc:
            say(f"{exc}: trying an earlier checkpoint")
            _log.warning("%s", exc)
            continue
        if at != frame:
            say(f"checkpoint '{path}' holds frame {at}, not {frame}: trying an earlier checkpoint")
            continue
        return at, state
    say(f"no usable checkpoint before frame {plan.first_frame}: the bake replays from frame {scene.frame_start}")
    return None, None


def _bake_locked(scene: BakeScene, cache_dir: Path, resume: bool,
                 progress: Optional[Callable[[BakeProgress], None]], stops: "_Stops",
                 say: Callable[[str], None], until: int) -> BakeResult:
    ledger = _plan.InputsLedger(scene)
    plan, previous = _plan_for(scene, cache_dir, resume, ledger, say)
    say(plan.text)

    def result(status: str, written: int = 0, resumed_from: Optional[int] = None, seconds: float = 0.0,
               last_frame: Optional[int] = None) -> BakeResult:
        return BakeResult(status=status, cache_dir=cache_dir, frames_written=written, last_frame=last_frame,
                          resumed_from=resumed_from, seconds=seconds,
                          seconds_per_frame=seconds / written if written else float("nan"),
                          damaged_frames=tuple(sorted(plan.damaged)), plan=plan)

    if plan.first_frame is None or plan.first_frame > until:
        say(f"nothing to bake up to frame {until}")
        return result("finished", last_frame=scene.frame_end if plan.first_frame is None else plan.first_frame - 1)
    resumed_from, state = _start_state(scene, cache_dir, plan, ledger, say)
    first = scene.frame_start if resumed_from is None else resumed_from + 1
    manifest = _cache.BakeManifest(cache_dir, scene, ledger, previous)
    t0 = time.perf_counter()
    with make_simulation(scene) as sim:
        # a bad pose fails here, and a cancel returns here, before the old bake is touched
        if not check_trajectory(sim, scene, first, stops.cancelled) or stops.cancelled():
            say("cancelled before the first step; the cache is as it was")
            return result("cancelled", resumed_from=resumed_from, seconds=time.perf_counter() - t0,
                          last_frame=plan.last_kept_frame)
        if state is not None:
            sim.set_state(state)
        manifest.start_session(plan, resumed_from, sim.device.get("renderer"))
        manifest.save()
        say(f"baking frames {plan.first_frame}..{until} of {scene.frame_start}..{scene.frame_end} at "
            f"{'x'.join(map(str, scene.grid_resolution))} cells ({scene.cell_size * 1000:.4g} mm) on the "
            f"{sim.device['backend'].upper()} backend ({manifest.session['device']}) into {cache_dir}"
            + (f", from the checkpoint at {resumed_from}" if resumed_from is not None else ""))
        status, written = _run_frames(sim, scene, ledger, plan, manifest, range(first, until + 1),
                                      _Callbacks(progress, stops, say, t0))
    seconds = time.perf_counter() - t0
    if status == "cancelled":
        say(f"cancelled; {written} frame(s) written this session; resume continues after frame "
            f"{manifest.last_frame}")
    return result(status, written, resumed_from, seconds, manifest.last_frame)


@dataclass(frozen=True)
class _Stops:
    """When the bake stops: cancelled (between substeps, every frame stepped still written) and
    now (cancelled, and the frames waiting for the writer dropped)."""

    cancelled: Callable[[], bool]
    now: Callable[[], bool]


@dataclass(frozen=True)
class _Callbacks:
    """A bake session's callers: progress and log (on the bake's thread), cancel, and its start."""

    progress: Optional[Callable[[BakeProgress], None]]
    stops: _Stops
    say: Callable[[str], None]
    t0: float  # time.perf_counter() when the session started


def _run_frames(sim: "hf.Simulation", scene: BakeScene, ledger: _plan.InputsLedger, plan: _plan.RebakePlan,
                manifest: "_cache.BakeManifest", frames: range, calls: _Callbacks) -> Tuple[str, int]:
    """Step ``frames`` (substeps_for_frame each, the probe and source moved per substep) and hand
    every frame from the plan's first frame to write on to the writer thread: its file, its
    checkpoint (kept every checkpoint_every frames and at a chunk's end), its record in the
    manifest, in that order. Frames before it are replayed without writing (their files are kept).
    Returns (status, frames written): 'finished', or 'cancelled' when asked between substeps."""
    write_from, until = plan.first_frame, frames[-1]
    fingerprint = scene.fingerprint()
    every = scene.checkpoint_every
    written, status, solver = 0, "finished", _SolverTally()

    def write_job(job: _writer.FrameJob) -> None:  # on the writer thread, one frame after the other
        path = write_frame(scene, job.state, job.frame, job.substeps)
        record = {**_verify.frame_record(path), "inputs": ledger.frames[job.frame]}
        _cache.save_checkpoint(manifest.cache_dir, job.frame, job.state, fingerprint,
                               inputs_sha256=ledger.chain(job.frame))
        keep = (every > 0 and (job.frame - scene.frame_start + 1) % every == 0) or (job.frame == until < scene.frame_end)
        manifest.record_frame(job, record, _cache.keep_checkpoint(manifest.cache_dir, job.frame) if keep else None)
        manifest.save()

    def report_written() -> None:  # on this thread: the log and progress callbacks
        nonlocal written
        for w in writer.finished():
            written += 1
            done = _progress(scene, w.frame, write_from, written, w.substeps, w.substeps, calls.t0, True)
            calls.say(f"frame {w.frame}: {w.substeps} substeps, {w.step_s:.2f} s; files {w.write_s:.2f} s on the "
                      f"writer thread; {done.frames_done}/{scene.frame_count} done, about {done.eta_s:.0f} s left")
            if calls.progress is not None:
                calls.progress(done)

    writer = _writer.FrameWriter(write_job, abort_when=calls.stops.now)
    try:
        for frame in frames:
            n = substeps_for_frame(scene, sim, frame)
            dt = scene.frame_dt / n
            frame_t0 = time.perf_counter()
            for s in range(n):
                report_written()
                writer.check()
                if calls.stops.cancelled():
                    status = "cancelled"
                    break
                if scene.probe is not None:
                    _apply_substep_probe(sim, scene.probe, frame, s, n, dt)
                if scene.source is not None:
                    _apply_substep_source(sim, scene.source, frame, s, n)
                solver.add(sim.step(dt))
                if calls.progress is not None:
                    calls.progress(_progress(scene, frame, write_from, written, s + 1, n, calls.t0, False))
            if status == "cancelled":
                break
            if frame < write_from:  # replaying up to the first frame to write: this one's file is kept
                continue
            frame_state = sim.state()  # one read of the fields: the frame file and the checkpoint
            writer.put(_writer.FrameJob(frame, n, frame_state, time.perf_counter() - frame_t0,
                                        pressure=solver.record()))
    except BaseException as exc:
        # A second Ctrl-C stops now (the frame being written still lands whole); any other
        # error lets the frames already stepped (sound) land before it surfaces.
        writer.close(abort=isinstance(exc, KeyboardInterrupt))
        report_written()
        raise
    writer.close()
    report_written()
    writer.check()
    return status, written


def _progress(scene: BakeScene, frame: int, first: int, written: int, substep: int, substeps: int,
              t0: float, finished: bool) -> BakeProgress:
    elapsed = time.perf_counter() - t0
    done_before = first - scene.frame_start
    remaining = scene.frame_end - first + 1 - written
    eta = elapsed / written * remaining if written else float("nan")
    return BakeProgress(frame=frame, frame_start=scene.frame_start, frame_end=scene.frame_end,
                        frames_done=done_before + written, substep=substep, substeps=substeps,
                        elapsed_s=elapsed, eta_s=eta, frame_finished=finished)
