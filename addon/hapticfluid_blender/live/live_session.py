# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session's controller: a plain class, no drawing and no operator, testable headless.

``LiveController(scene)`` reads everything it needs from bpy on the main thread (``read_plan``),
then a worker thread (which never touches bpy) opens the device, makes the Simulation and the
HapticSession and starts it, so a Falcon's firmware upload or the GL context never freezes
Blender. ``tick()`` runs on the main thread ~30-60 times a second: it pushes the probe object's
pose to the host device (Mouse, Timeline) or moves the object to the device pose (Falcon,
Simulated Falcon), takes the newest field snapshot if its sequence changed, copies the stats
into the scene's live properties and records keys while recording. ``stop()`` ramps the force
down through the session's slew limit, joins the threads and returns a report (or None).

Every bad setup raises (or, found by the worker, ends the session with) a ``SessionError`` whose
message starts with the fix.
"""

import logging
import math
import os
import threading
import time
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

import bpy

from ..bake import blender_scene
from ..properties import roles

log = logging.getLogger(__name__)

HOST_MODES = ("MOUSE", "TIMELINE")     # the object's transform drives the probe
DEVICE_MODES = ("FALCON", "SIMULATED_FALCON")  # the device drives the object
SNAPSHOT_INTERVAL_S = 1.0 / 60.0       # newest fields for the viewport at most this often (wall s)
# Falcon modes keep the device's poses of every haptic period this long (s) for Record: each tick
# takes them, so Record keys the hand's path between ticks however rarely Blender ticks.
TRACE_SECONDS = 5.0
TRACE_SAMPLES_PER_KEY = 4              # of the trace, Record keeps this many poses per key interval
STOP_TIMEOUT_S = 10.0                  # stop() waits this long for the simulation's current step


class SessionError(Exception):
    """A live session cannot start or had to end; the message starts with the fix."""


@dataclass
class LivePlan:
    """What the worker needs, read from bpy on the main thread (plain values only)."""

    mode: str
    probe_name: str
    resolution: Optional[int]          # cells along the longest edge; None: by the GL renderer
    domain_lo: Tuple[float, float, float]
    domain_hi: Tuple[float, float, float]
    fluid: Dict[str, Any]
    source: Optional[Dict[str, Any]]
    probe_shape: Dict[str, Any]        # blender_scene.probe_shape_dict
    probe_matrix: List[List[float]]    # matrix_world at the start (rows)
    session_args: Dict[str, Any]       # HapticSession keyword arguments (SI)
    auto_workspace: bool
    max_force: float                   # N
    firmware: Optional[str] = None
    show_temperature: bool = False
    hand_gesture: str = "rest"         # the simulated Falcon's hand (hapticfluid.hand_gestures)
    feel_playback: bool = True         # Falcon modes: guide the grip along the keys played (set_guide)
    viewport_first: bool = True        # on a CPU GL device the simulation yields the cores to drawing


@dataclass
class _Recording:
    obj_name: str
    rotation_path: str
    start_frame: float
    fps: float
    interval_s: float
    t0: float
    # Frame-locked (the timeline plays): a sample's frame is the frame played when it was performed
    # (clock_frames maps the clock to the played frame), and Record-off keys the frame then played
    # (B), so the take replaces exactly the frames A..B that played. Otherwise the frame is
    # start_frame + elapsed x fps (a performance recorded over a still timeline).
    frame_locked: bool = False
    clock_frames: List[Tuple[float, float]] = field(default_factory=list)  # (clock s, frame played)
    muted: List[Tuple[str, int, bool]] = field(default_factory=list)  # (path, index, mute before) punched in
    trace_t: float = -math.inf         # clock time of the last trace pose kept (s)
    looped: bool = False               # the timeline jumped back: samples after it are not kept
    # (frame, location, rotation) of the object at every tick: the motion performed, as Blender
    # knew it (a drag moves the object once per pass of the event loop, as often as it redraws)
    samples: List[Tuple[float, Tuple[float, ...], Tuple[float, ...]]] = field(default_factory=list)

    def frame_at(self, t: float) -> Optional[float]:
        """The frame a pose performed at clock time t belongs to; None before the take."""
        if t < self.t0:
            return None
        if not self.frame_locked:
            return self.start_frame + (t - self.t0) * self.fps
        pairs = self.clock_frames
        if not pairs or t <= pairs[0][0]:
            return self.start_frame
        for (ta, fa), (tb, fb) in zip(pairs, pairs[1:]):
            if t <= tb:
                return fa + (fb - fa) * (t - ta) / (tb - ta) if tb > ta else fb
        return pairs[-1][1]


def _import_hf():
    """The hapticfluid package, with the modules the worker thread uses already imported: a first
    import reads files through the import machinery, and it runs here, on the main thread (read_plan),
    not on the worker (Blender 3.4 in a window once segfaulted reading a .pyc in the worker's first
    import of hapticfluid.assembly while its main thread ran); later imports are look-ups."""
    try:
        import hapticfluid
        from hapticfluid import assembly, hand_gestures  # noqa: F401  (imported for the worker)
    except ImportError as exc:
        raise SessionError(f"Install the hapticfluid package where Blender's Python finds it (see README: "
                           f"pip install into Blender's Python, or PYTHONPATH): it is not importable ({exc})") from None
    return hapticfluid


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:]


def read_plan(scene) -> LivePlan:
    """Main thread: the scene's roles and settings -> LivePlan, or SessionError (fix first)."""
    _import_hf()  # the first thing to fix if it fails
    bake = roles.settings_of(scene)
    live = scene.hapticfluid_live
    try:
        lo, hi = blender_scene.domain_box(bake)
    except blender_scene.SceneError as exc:
        raise SessionError(_sentence(str(exc))) from None
    if min(hi[i] - lo[i] for i in range(3)) <= 0.0:
        raise SessionError(f"Give the domain '{bake.domain.name}' a volume: its bounding box is flat")
    probe = bake.probe
    if probe is None:
        raise SessionError(f"Give an object the Probe role ({roles.PHYSICS_PATH}): the object that pushes the smoke")
    if probe.name not in scene.objects:
        raise SessionError(f"Link the probe '{probe.name}' into this scene: it is not in scene '{scene.name}'")
    try:
        shape = blender_scene.probe_shape_dict(probe, bake.probe_shape)
    except blender_scene.SceneError as exc:
        raise SessionError(_sentence(str(exc))) from None
    plo, phi = blender_scene.world_box(probe) if probe.type == "MESH" else (
        [probe.matrix_world.translation[i] - shape.get("radius", 0.0) for i in range(3)],
        [probe.matrix_world.translation[i] + shape.get("radius", 0.0) for i in range(3)])
    if any(plo[i] < lo[i] or phi[i] > hi[i] for i in range(3)):
        raise SessionError(f"Move the probe '{probe.name}' inside the domain '{bake.domain.name}': its box "
                           f"{_box_text(plo, phi)} reaches outside the domain {_box_text(lo, hi)}")
    firmware = None
    if live.device == "FALCON" and live.firmware_path:
        firmware = bpy.path.abspath(live.firmware_path)
        if not os.path.isfile(firmware):
            raise SessionError(f"Choose the Falcon firmware file (Novint's nvent_firmware.bin) in the sidebar: "
                               f"'{firmware}' does not exist")
    session_args = {
        "force_gain": None if live.auto_force_gain else live.force_gain,  # None: the engine derives it
        "allow_unsafe_gain": (not live.auto_force_gain) and live.allow_unsafe_gain,
        "feel": live.feel.lower(),  # with a derived gain: amplified or physical (1:1)
        "filter": "lowpass",
        "bandwidth_ratio": live.bandwidth_ratio,
        "prediction": live.prediction,
        "max_force": live.max_force,
        "probe_radius": None,  # keep the probe the simulation was given (sphere or mesh)
        "snapshot": SNAPSHOT_INTERVAL_S,
        "snapshot_temperature": live.show_temperature,
    }
    if live.device in HOST_MODES:  # the device frame is the world: the pose pushed is the object's
        session_args.update(workspace_scale=1.0, workspace_offset=(0.0, 0.0, 0.0))
    elif not live.auto_workspace:
        session_args.update(workspace_scale=live.workspace_scale, workspace_offset=tuple(live.workspace_offset))
    if live.device in DEVICE_MODES:  # the hand's pose at every haptic period, for Record (_take_trace)
        session_args.update(trace=True, trace_seconds=TRACE_SECONDS)
    return LivePlan(
        mode=live.device, probe_name=probe.name, resolution=None if live.auto_resolution else live.resolution,
        domain_lo=tuple(lo), domain_hi=tuple(hi), fluid=blender_scene.fluid_dict(scene, bake),
        source=blender_scene.source_dict(bake), probe_shape=shape,
        probe_matrix=[list(row) for row in probe.matrix_world], session_args=session_args,
        auto_workspace=live.auto_workspace and live.device in DEVICE_MODES, max_force=live.max_force,
        firmware=firmware, show_temperature=live.show_temperature, hand_gesture=live.hand_gesture.lower(),
        feel_playback=live.feel_playback, viewport_first=viewport_first(live.cpu_share, live.device))


def _gl_context_problem(exc) -> str:
    return (f"Check the GPU driver (or set HAPTICFLUID_EGL_DEVICE, see README): the simulation's "
            f"GL context could not be made: {exc}")


def _box_text(lo, hi) -> str:
    return "(" + ", ".join(f"{a:.3g}..{b:.3g}" for a, b in zip(lo, hi)) + ") m"


def viewport_first(cpu_share: str, mode: str) -> bool:
    """Whether the simulation yields the cores to Blender's drawing (on a CPU GL device): CPU Share
    'VIEWPORT', or 'AUTO' in the modes where the viewport is what the user follows (Mouse,
    Timeline); with a Falcon the hand's force needs the simulation's rate, so 'AUTO' shares equally."""
    return cpu_share == "VIEWPORT" or (cpu_share == "AUTO" and mode not in DEVICE_MODES)


def preview_resolution(software: bool) -> int:
    """Cells along the longest edge when the resolution is automatic: a software renderer
    (llvmpipe) steps 32^3 at about 40 Hz, a hardware GPU 64^3 faster still."""
    return 32 if software else 64


class _Engine:
    """The hapticfluid objects of one session, made on the worker thread (no bpy there)."""

    def __init__(self):
        self.sim = None
        self.device = None
        self.session = None
        self.resolution = None
        self.workspace_box = None  # (lo, hi) world m for device modes

    def build(self, plan: LivePlan):
        hf = _import_hf()
        from hapticfluid import assembly

        self.device = self._open_device(hf, plan)
        size = [plan.domain_hi[i] - plan.domain_lo[i] for i in range(3)]
        try:  # the EGL device the simulation will use (HAPTICFLUID_EGL_DEVICE may name a bad one)
            software = bool(hf.probe_device().get("software", True))
        except hf.HapticFluidError as exc:
            raise SessionError(_gl_context_problem(exc)) from None
        res = plan.resolution if plan.resolution is not None else preview_resolution(software)
        try:
            settings = assembly.fluid_settings(plan.domain_lo, size, res, plan.fluid,
                                               thread_niceness=assembly.live_thread_niceness(software,
                                                                                             plan.viewport_first))
        except (hf.InvalidArgumentError, TypeError) as exc:
            raise SessionError(_fix_first(str(exc))) from None
        source = None
        if plan.source is not None:  # a mesh source is held where it is at Start
            s = plan.source
            source = dict(shape="mesh" if s.get("shape") == "mesh" else "sphere", density=s["density"],
                          temperature=s["temperature"], centre=s.get("centre"), radius=s.get("radius"),
                          matrix=s.get("matrix"), vertices=s.get("vertices"), triangles=s.get("triangles"))
        shape = plan.probe_shape
        probe = dict(shape=shape["shape"], matrix=plan.probe_matrix, radius=shape.get("radius"),
                     vertices=shape.get("vertices"), triangles=shape.get("triangles"))
        try:
            self.sim = hf.Simulation(settings)
        except hf.HapticFluidError as exc:
            raise SessionError(_gl_context_problem(exc)) from None
        try:
            if source is not None:
                assembly.place_source(self.sim, **source)
        except hf.InvalidArgumentError as exc:
            raise SessionError(_fix_first(f"smoke source: {exc}")) from None
        try:
            assembly.place_probe(self.sim, **probe)
        except hf.MeshNotClosedError as exc:
            raise SessionError(f"Close the probe '{plan.probe_name}' mesh (Edit Mode: Mesh > Clean Up > Fill Holes, "
                               f"then Mesh > Normals > Recalculate Outside) or use the Sphere probe shape: "
                               f"{exc}") from None
        except hf.InvalidArgumentError as exc:
            raise SessionError(_fix_first(str(exc))) from None
        self.resolution = settings.resolution
        try:
            self.session = hf.HapticSession(self.sim, self.device,
                                            assembly.session_settings(plan.session_args, plan.auto_workspace))
        except hf.InvalidArgumentError as exc:
            raise SessionError(_fix_first(str(exc))) from None
        if plan.mode in DEVICE_MODES:  # where the engine maps the device's workspace
            lo, hi = self.session.workspace_box
            self.workspace_box = (tuple(float(x) for x in lo), tuple(float(x) for x in hi))
        if plan.mode in HOST_MODES:  # the first pose the haptic thread reads is the object's
            matrix = plan.probe_matrix
            self.device.push_pose(tuple(matrix[r][3] for r in range(3)), orientation=probe_rotation(matrix))
        self.session.start()

    @staticmethod
    def _open_device(hf, plan: LivePlan):
        if plan.mode in HOST_MODES:
            return hf.host_device(max_force=plan.max_force)
        if plan.mode == "SIMULATED_FALCON":
            from hapticfluid import hand_gestures

            return hf.open_simulated_falcon(max_force=plan.max_force, **hand_gestures.falcon_args(plan.hand_gesture))
        try:
            # No homing wait: the session commands no force until the user has homed it.
            return hf.open_falcon(firmware=plan.firmware, home=False, max_force=plan.max_force)
        except hf.DeviceAccessDeniedError as exc:  # the driver's message ends with the udev rule to install
            raise SessionError(f"Install the udev rule below, then unplug and replug the Falcon: {exc}") from None
        except hf.DeviceNotFoundError:
            raise SessionError("Plug in the Falcon's USB cable and power supply, or choose the Simulated Falcon "
                               "device (no Novint Falcon is plugged in)") from None
        except hf.HapticFluidError as exc:
            raise SessionError(_fix_first(f"Falcon: {exc}")) from None

    def close(self):
        """Stops the session (force slewed to zero, threads joined) and frees the device and GPU;
        returns the report for the error that ended the session (fix first), or None."""
        error = None
        if self.session is not None:
            failed = self.session.state == "failed"
            try:
                self.session.stop(timeout=STOP_TIMEOUT_S)
            except Exception as exc:  # the error that ended the session (device gone, solver) or a slow step
                error = _failure_report(exc) if failed else _fix_first(str(exc))
                try:
                    self.session.stop(timeout=STOP_TIMEOUT_S)  # a slow last step: once more
                except Exception:
                    pass
        if self.device is not None:
            self.device.close()
        if self.sim is not None:
            self.sim.close()
        return error


def _fix_first(message: str) -> str:
    """An engine message as a report, fix first: the engine's messages say what is wrong, then
    after '; ' (or ': plug ...') what to do."""
    for marker in ("; ", ": plug "):
        i = message.rfind(marker)
        if i > 0:
            fix = message[i + len(marker):].strip()
            if marker == ": plug ":
                fix = "plug " + fix
            if fix:
                return f"{fix[:1].upper()}{fix[1:]} ({message[:i]})"
    return message


def _failure_report(error: Exception) -> str:
    """The report for a session the engine ended (fix first, then the engine's words): the device's
    error (a hapticfluid.DeviceError: unplugged, powered off) or the simulation thread's."""
    if isinstance(error, _import_hf().DeviceError):
        return f"Check the device's cable and power, then start the session again: {error}"
    return (f"Start the session again (the fluid is reset); if it recurs, raise the pressure iterations or move "
            f"the probe more slowly: {error}")


class LiveController:
    """One live session of one scene. Main thread only (bpy); the engine runs on its own threads."""

    def __init__(self, scene, drawer=None, clock=time.monotonic):
        self.scene = scene
        self.scene_name = scene.name
        self.drawer = drawer
        self.clock = clock
        self.plan = read_plan(scene)  # SessionError on a bad setup, before any thread starts
        bake = roles.settings_of(scene)
        self.probe = bake.probe
        self.domain = bake.domain
        self.probe_name = self.probe.name
        self.domain_name = self.domain.name
        self.start_matrix = self.probe.matrix_world.copy()
        self.force_origin = tuple(self.start_matrix.translation)  # where the force arrow was last drawn (m)
        self.engine = _Engine()
        self.state = "starting"   # starting -> running -> stopped
        self.report = None        # why it ended (None: stopped by the user without error)
        self.recording = None
        self.keys_written = 0
        self.last_sequence = 0
        self.ticks = 0
        self._display = None
        self.last_take = None     # (A, B, looped) of the last take keyed: its frames
        self._guiding = False     # the engine has a played pose (Feel Playback)
        self._played_clock = None  # (clock, frame) at the last played pose: the playback's pace
        # Whether the timeline plays (a screen's animation playback); tests without a window
        # replace it, as scene.frame_set() then stands in for playback.
        self.timeline_playing = timeline_playing
        self._worker_error = None
        self._worker = threading.Thread(target=self._build, name="hapticfluid-live-start", daemon=True)
        self._worker.start()

    # -- worker -----------------------------------------------------------------------------
    def _build(self):
        try:
            self.engine.build(self.plan)
        except SessionError as exc:
            self._worker_error = str(exc)
        except Exception as exc:  # anything else the engine raised: still a report, never a traceback
            self._worker_error = f"Report this as a bug: the live session failed to start: {type(exc).__name__}: {exc}"

    def wait_started(self, timeout=120.0):
        """Blocks until the worker has finished (for scripts and tests); raises SessionError if the
        session could not start."""
        self._worker.join(timeout)
        self.tick()
        if self.state == "stopped" and self.report:
            raise SessionError(self.report)
        if self.state != "running":
            raise SessionError(f"Wait longer or lower the preview resolution: the session did not start in {timeout} s")

    # -- main thread ----------------------------------------------------------------------
    @property
    def live(self):
        return self.scene.hapticfluid_live

    @property
    def session(self):
        return self.engine.session

    def refresh_references(self):
        """An undo (memfile) re-reads the file's data: the Python references to the scene, the probe
        and the domain die (ReferenceError) though the objects are still there. Finds them again by
        name, so an undo during the session (after a take, say) does not end it as if they were
        deleted; one really deleted stays gone and ends the session at the next tick."""
        try:
            self.scene.name  # noqa: B018
        except ReferenceError:
            scene = bpy.data.scenes.get(self.scene_name)
            if scene is None:
                return
            self.scene = scene
        for attr, name in (("probe", self.probe_name), ("domain", self.domain_name)):
            try:
                getattr(self, attr).name  # noqa: B018
            except ReferenceError:
                obj = bpy.data.objects.get(name)
                if obj is not None:
                    setattr(self, attr, obj)

    def tick(self):
        """One main-thread update; returns the state ('starting', 'running' or 'stopped')."""
        self.refresh_references()
        if self.state == "starting":
            if self._worker.is_alive():
                return self.state
            if self._worker_error is not None:
                self._end(self._worker_error)
                return self.state
            self.state = "running"
            self._on_started()
        if self.state != "running":
            return self.state
        problem = self._lost_object()
        if problem:
            self._end(problem)
            return self.state
        session = self.session
        if session.state == "failed":
            self._end(None)  # the engine's error, reported by its type (engine.close)
            return self.state
        now = self.clock()
        self.ticks += 1
        latest = session.latest()
        if self.plan.mode in HOST_MODES:  # location and rotation: the probe turns with the object
            m = self.probe.matrix_world
            self.engine.device.push_pose(tuple(m.translation), orientation=probe_rotation(m))
            self._check_scale(m)
        else:
            if self._plays_keys():  # the keys move the object (and, guided, the fluid's probe)
                self._guide_along_keys(now)
            else:  # the device moves the object (and the fluid's probe)
                self._release_guide()
                self._follow_device(latest)
            self._take_trace()
        self._update_drawer(latest)
        self._update_stats(latest)
        if self.recording is not None:
            self._sample(now)
        return self.state

    def _on_started(self):
        live = self.live
        live.is_running = True
        live.resolution_used = max(self.engine.resolution)
        live.status = f"running at {'x'.join(map(str, self.engine.resolution))} cells"
        if self.drawer is not None:
            self.drawer.set_domain(self.plan.domain_lo, self.plan.domain_hi)
            self.drawer.set_workspace_box(*(self.engine.workspace_box or (None, None)))
            self.drawer.set_probe(self.plan.probe_shape)  # the smoke's rays stop at the probe
            self.drawer.set_probe_matrix([list(row) for row in self.probe.matrix_world])
            # Arrow, label and the smoke's stop at the probe follow the object at every redraw.
            self.drawer.set_probe_source(self._drawn_probe_matrix)
        # The smoke is drawn inside the domain and hidden by anything in front of it (the scene's
        # depth): a solid domain would hide it all, so it is drawn as wire, as the bake does.
        if self.domain.display_type in ("SOLID", "TEXTURED"):
            self.domain.display_type = "WIRE"

    def _drawn_probe_matrix(self):
        """The probe object's matrix_world now (what Blender draws it with), or None once deleted."""
        try:
            return self.probe.matrix_world
        except ReferenceError:
            return None

    def _lost_object(self) -> Optional[str]:
        for obj, name, role in ((self.probe, self.probe_name, "probe"), (self.domain, self.domain_name, "domain")):
            try:
                linked = obj.name in self.scene.objects
            except ReferenceError:
                linked = False
            if not linked:
                return f"Start the session again with a {role}: the {role} '{name}' was deleted"
        return None

    def _check_scale(self, matrix):
        """The session keeps the probe's scale from Start; a scale changed since says so in the status."""
        start = [self.start_matrix.col[c].to_3d().length for c in range(3)]
        now = [matrix.col[c].to_3d().length for c in range(3)]
        changed = any(abs(a - b) > 1e-4 * max(a, b) for a, b in zip(start, now))
        note = "; the probe's new scale applies at the next Start"
        status = self.live.status
        if changed and not status.endswith(note):
            self.live.status = status + note
        elif not changed and status.endswith(note):
            self.live.status = status[:-len(note)]

    def _follow_device(self, latest):
        from mathutils import Vector

        m = self.start_matrix.copy()  # where the engine puts the probe: mapped and held off the walls
        m.translation = Vector(tuple(float(x) for x in self.session.probe_origin(latest["position"])))
        self.probe.matrix_world = m

    def _guide_along_keys(self, now):
        """Haptic playback (Feel Playback on): the pose the keys play now, with its velocity, goes to
        the engine each tick (HapticSession.set_guide): the fluid's probe follows the keys, and the
        device pulls the grip along them so the hand feels the existing motion and the fluid's force
        on it. The velocity is the keys' slope at this frame times the frames played per second of
        wall time (measured when the frame moves on, smoothed: playback may drop or repeat frames);
        between frame changes the pose is carried along that slope, at most one frame ahead, so
        ticks faster than the frames do not pull the target back to the frame shown."""
        if not self.plan.feel_playback:
            return
        obj = self.probe
        frame = float(self.scene.frame_current_final)
        fps = self.scene.render.fps / self.scene.render.fps_base
        last = self._played_clock  # (clock, frame, frames per second) when the frame last moved on
        if last is None or frame < last[1]:  # (re)started, or playback looped / scrubbed back
            last = (now, frame, fps)
        elif frame > last[1]:
            measured = (frame - last[1]) / max(now - last[0], 1e-3)
            last = (now, frame, min(4.0 * fps, max(0.25 * fps, 0.5 * (last[2] + measured))))
        self._played_clock = last
        rate = last[2]
        ahead = min(1.0, rate * (now - last[0]))  # frames since the frame moved on
        curves = object_fcurves(obj)
        slope = []
        for i in range(3):
            fc = curves.find("location", index=i)
            slope.append(0.0 if fc is None or fc.mute else fc.evaluate(frame + 0.5) - fc.evaluate(frame - 0.5))
        if obj.parent is not None:  # local location -> world: the parent's turn and scale
            from mathutils import Vector

            slope = list((obj.parent.matrix_world.to_3x3() @ obj.matrix_parent_inverse.to_3x3()) @ Vector(slope))
        position = tuple(float(c) + ahead * float(d) for c, d in zip(obj.matrix_world.translation, slope))
        velocity = tuple(float(c) * rate for c in slope)
        try:
            self.session.set_guide(position, velocity)
            self._guiding = True
        except _import_hf().InvalidArgumentError as exc:  # a key far off the scale: said, not fatal
            self._release_guide()
            self.live.status = f"Feel Playback paused: {exc}"

    def _release_guide(self):
        """Lets go of the played pose (at Record, when playback stops): the guide fades out over its ramp
        and the fluid's probe goes back to the grip, which the guide kept near the keys."""
        self._played_clock = None
        if self._guiding:
            self._guiding = False
            self.session.release_guide()

    def _plays_keys(self) -> bool:
        """Device modes: while the timeline plays and Record is off, a probe with location keys
        follows them (the object is drawn where the existing motion puts it, so the user sees
        where to punch in); with Feel Playback the fluid's probe follows them too and the device
        guides the grip along them (_guide_along_keys; ARCHITECTURE.md, Live session: Punch-in)."""
        if self.recording is not None or not self.timeline_playing():
            return False
        data = self.probe.animation_data
        if data is None or data.action is None:
            return False
        return object_fcurves(self.probe).find("location", index=0) is not None

    def _take_trace(self):
        """Device modes: the device's poses since the last tick (one per haptic period); while
        recording, those TRACE_SAMPLES_PER_KEY times per key interval become samples of the
        object's location (where the engine puts the probe for that pose, less the object's parent offset)
        at the frames they were performed at (played frames when frame-locked), so Record keys the
        hand's path, not the straight line between ticks. Needs the controller's clock to be the
        trace's (time.monotonic, CLOCK_MONOTONIC)."""
        trace = self.session.trace()
        r = self.recording
        if r is None or self.clock is not time.monotonic:
            return
        if r.frame_locked:
            self._mark_frame(self.clock())  # after trace(): every pose it gave is older than this
        if r.looped or not len(trace["time"]):
            return
        obj = self.probe
        world_now = obj.matrix_world.translation
        parent = tuple(world_now[i] - obj.location[i] for i in range(3))  # a parent's translation
        rotation = tuple(getattr(obj, r.rotation_path))  # Falcon modes keep the start rotation
        spacing = r.interval_s / TRACE_SAMPLES_PER_KEY
        origins = self.session.probe_origin(trace["position"])  # where the engine put the probe
        for t, w in zip(trace["time"], origins):
            t = float(t)
            if t < r.trace_t + spacing:
                continue
            frame = r.frame_at(t)
            if frame is None or (r.samples and frame <= r.samples[-1][0]):
                continue
            r.trace_t = t
            location = tuple(float(w[i]) - parent[i] for i in range(3))
            r.samples.append((frame, location, rotation))

    def _mark_frame(self, t):
        """Frame-locked recording: the frame played at clock time t (kept when it moved on). A
        frame before the last one (playback looped at the end frame, or the user scrubbed back)
        ends the take's samples: the keys cover the frames played once, in order."""
        r = self.recording
        frame = float(self.scene.frame_current_final)
        last = r.clock_frames[-1][1] if r.clock_frames else -math.inf
        if frame < last:
            r.looped = True
        elif frame > last:
            r.clock_frames.append((t, frame))

    def _update_drawer(self, latest):
        snap = self.session.snapshot()
        if snap is not None and snap["sequence"] != self.last_sequence:
            self.last_sequence = snap["sequence"]
            if self.drawer is not None:
                self.drawer.set_density(snap["density"], snap["temperature"])
        if self.drawer is not None:
            display = (self.live.density_scale, self.live.show_temperature)
            if display != self._display:  # the user may change them during the session
                self._display = display
                self.drawer.set_display(*display)
            self.force_origin = tuple(self.probe.matrix_world.translation)
            self.drawer.set_probe_matrix([list(row) for row in self.probe.matrix_world])
            self.drawer.set_force(self.force_origin, self.hand_force_world(latest), self.plan.max_force)

    def hand_force_world(self, latest) -> Tuple[float, float, float]:
        """The force the hand feels (N): the device's commanded force (after the force gain, the
        filter and the safety stage) in world axes, as the engine reports it (latest()'s
        commanded_force_world: its workspace map flips a mirrored axis back). Drawn against Max
        Force, the device's limit, in the same newtons."""
        return tuple(float(c) for c in latest["commanded_force_world"])

    def _update_stats(self, latest):
        s = self.session.stats()
        live = self.live
        live.sim_rate_hz = s["sim_rate_hz"]
        live.haptic_rate_hz = s["haptic_rate_hz"]
        live.jitter_p99_ms = s["jitter_p99_ms"]
        live.latency_p50_ms = s["latency_p50_ms"]
        live.latency_p99_ms = s["latency_p99_ms"]
        live.force_n = float(sum(c * c for c in latest["sim_force"]) ** 0.5)
        live.device_force_n = float(sum(c * c for c in latest["commanded_force"]) ** 0.5)
        live.realtime = bool(s["realtime"])
        live.force_gain_used = s.get("force_gain", 0.0)
        live.force_gain_reason = s.get("force_gain_reason", "")
        live.device_state = (f"{self.engine.device.info().name}: {'homed' if latest['homed'] else 'not homed'}, "
                             f"buttons {latest['buttons']:#x}")
        live.scheduling = s["scheduling"]

    # -- recording ------------------------------------------------------------------------
    def start_recording(self):
        """Record on. Frame-locked when the timeline plays (and always in Timeline mode): the take
        starts at the frame playing (A) and its samples belong to the frames played. Mouse and
        Falcon modes then punch in: the probe's location and rotation F-curves are muted until
        Record-off so the performance, not the existing keys, moves the probe."""
        if self.state != "running":
            raise SessionError("Start the live session first: Record keys the motion performed during it")
        scene = self.scene
        obj = self.probe
        path = {"QUATERNION": "rotation_quaternion", "AXIS_ANGLE": "rotation_axis_angle"}.get(
            obj.rotation_mode, "rotation_euler")
        now = self.clock()
        locked = self.plan.mode == "TIMELINE" or bool(self.timeline_playing())
        r = _Recording(obj_name=obj.name, rotation_path=path, start_frame=float(scene.frame_current_final),
                       fps=scene.render.fps / scene.render.fps_base, interval_s=1.0 / self.live.record_rate,
                       t0=now, frame_locked=locked)
        if locked:
            r.clock_frames.append((now, r.start_frame))
            if self.plan.mode != "TIMELINE":
                r.muted = _mute_channels(obj, ("location", path))
        self.recording = r
        self.live.is_recording = True
        if self.plan.mode in DEVICE_MODES:  # the object played the keys until now: the grip's pose at A
            self._release_guide()  # the probe goes back to the grip, which the guide kept near the keys
            self._follow_device(self.session.latest())
        self._sample(now)

    def _sample(self, now):
        r = self.recording
        if r.frame_locked:
            self._mark_frame(now)
            if r.looped:
                return
            frame = float(self.scene.frame_current_final)
        else:
            frame = r.start_frame + (now - r.t0) * r.fps
        if r.samples and frame <= r.samples[-1][0]:
            return
        obj = self.probe
        r.samples.append((frame, tuple(obj.location), tuple(getattr(obj, r.rotation_path))))

    def stop_recording(self, before_write=None) -> int:
        """Writes the motion performed as keys at the record rate (replacing the keys in their frame
        range, every key outside it left as it was, bit for bit); returns the number of poses keyed.
        Each key is the pose at its time on the path performed: between two samples, location and
        Euler or axis-angle rotation linearly, a quaternion normalized-linearly (resample), so keys
        come at the record rate however often Blender redrew while recording. Frame-locked, the
        take ends with a key at B, the frame played at Record-off, from the pose performed there,
        so the F-curves stay continuous into the keys after B. before_write() runs after muted
        channels are restored and before any key changes (the Record operator pushes an undo step
        there, so one undo restores the old keys)."""
        r, self.recording = self.recording, None
        self.live.is_recording = False
        if r is None:
            return 0
        try:
            obj = self.probe
            obj.name  # noqa: B018 (raises ReferenceError if it was deleted)
        except ReferenceError:
            return 0
        if r.frame_locked and not r.looped:
            if self.plan.mode in DEVICE_MODES and self.state == "running":
                self._follow_device(self.session.latest())
            self.recording = r
            self._sample(self.clock())  # the pose at B, unless a tick sampled B already
            self.recording = None
        _restore_mutes(obj, r.muted)
        if not r.samples or (r.frame_locked and len(r.samples) < 2):  # locked and no frame played: no take
            return 0
        keys = resample(r.samples, r.interval_s * r.fps, quaternion=r.rotation_path == "rotation_quaternion",
                        end=r.frame_locked)
        if before_write is not None:
            before_write()
        write_keys(obj, r.rotation_path, keys)
        self.keys_written += len(keys)
        self.last_take = (keys[0][0], keys[-1][0], r.looped)
        return len(keys)

    # -- ending ---------------------------------------------------------------------------
    def stop(self, reason: Optional[str] = None) -> Optional[str]:
        """Ends the session (force down through the slew limit, threads joined); the report to
        show (reason, or the error that ended it), or None."""
        if self.state == "stopped":
            return self.report
        if self.state == "starting":
            self._worker.join()
        self._end(reason)
        return self.report

    def _end(self, reason):
        if self.recording is not None:
            self.stop_recording()
        error = self.engine.close()
        self.state = "stopped"
        self.report = reason or error
        try:
            live = self.live
            live.is_running = False
            live.is_recording = False
            live.status = self.report or "stopped"
        except ReferenceError:  # the scene itself is gone
            pass
        if self.report:
            log.warning("hapticfluid live session ended: %s", self.report)


def timeline_playing() -> bool:
    """Whether Blender plays the animation (in any window)."""
    wm = bpy.context.window_manager
    return any(w.screen is not None and w.screen.is_animation_playing for w in (wm.windows if wm else ()))


def _mute_channels(obj, paths) -> List[Tuple[str, int, bool]]:
    """Mutes the object's F-curves of those paths (so playback leaves the channels to the
    performance); returns (path, index, mute before) to restore."""
    data = obj.animation_data
    if data is None or data.action is None:
        return []
    muted = []
    for fc in object_fcurves(obj):
        if fc.data_path in paths:
            muted.append((fc.data_path, fc.array_index, fc.mute))
            fc.mute = True
    return muted


def _restore_mutes(obj, muted):
    if not muted or obj.animation_data is None or obj.animation_data.action is None:
        return
    fcurves = object_fcurves(obj)
    for path, index, before in muted:
        fc = fcurves.find(path, index=index)
        if fc is not None:
            fc.mute = before


def probe_rotation(matrix) -> Tuple[float, float, float, float]:
    """The rotation of a probe's matrix_world (rows or a mathutils Matrix) as a quaternion
    (w, x, y, z), by the engine's rule (HapticSession::probeRotation): Gram-Schmidt on the x, then
    y column, z = x cross y, so a scaled or mirrored matrix gives the same proper rotation there
    and here; the engine keeps the rest as the probe's scale."""
    from mathutils import Matrix, Vector

    cols = [Vector([matrix[r][c] for r in range(3)]) for c in range(2)]
    x = cols[0].normalized()
    y = (cols[1] - cols[1].dot(x) * x).normalized()
    q = Matrix((x, y, x.cross(y))).transposed().to_quaternion()
    return (q.w, q.x, q.y, q.z)


def resample(samples, frames_per_key, quaternion=False, end=False):
    """(frame, location, rotation) samples at uneven frames -> the same path at frames
    samples[0] + k * frames_per_key up to the last sample's frame (end: and at the last sample's
    own frame, when the grid misses it): linear between the two samples around each, a quaternion
    rotation (w, x, y, z) normalized-linearly on the shorter arc."""
    if not samples:
        return []
    out = []
    first, last = samples[0][0], samples[-1][0]
    frames = []
    k = 0
    while first + k * frames_per_key <= last + 1e-9:
        frames.append(first + k * frames_per_key)
        k += 1
    if end and last - frames[-1] > 1e-6:
        frames.append(last)
    i = 0
    for frame in frames:
        while i + 1 < len(samples) - 1 and samples[i + 1][0] < frame:
            i += 1
        a = samples[i]
        b = samples[min(i + 1, len(samples) - 1)]
        span = b[0] - a[0]
        w = 0.0 if span <= 0.0 else min(1.0, max(0.0, (frame - a[0]) / span))
        location = tuple(x + w * (y - x) for x, y in zip(a[1], b[1]))
        rb = b[2]
        if quaternion and sum(x * y for x, y in zip(a[2], rb)) < 0.0:
            rb = tuple(-y for y in rb)  # the shorter way round
        rotation = tuple(x + w * (y - x) for x, y in zip(a[2], rb))
        if quaternion:
            norm = math.sqrt(sum(c * c for c in rotation)) or 1.0
            rotation = tuple(c / norm for c in rotation)
        out.append((frame, location, rotation))
    return out


# What a key is besides its point: kept, with co and handles, for every key outside a take.
_KEY_FIELDS = ("handle_left_type", "handle_right_type", "interpolation", "easing", "back", "amplitude", "period",
               "type")


def key_state(point):
    """A keyframe point as plain values: co, handle_left, handle_right, then _KEY_FIELDS."""
    return (tuple(point.co), tuple(point.handle_left), tuple(point.handle_right)) + tuple(
        getattr(point, name) for name in _KEY_FIELDS)


def write_keys(obj, rotation_path, samples):
    """Keys location and rotation at each (frame, location, rotation) sample into the object's
    action, first removing the keys of those channels within the samples' frame range. Keys
    outside the range keep their co, handles, handle types and interpolation bit for bit: Blender
    recomputes every automatic handle of a curve when keys are added (fc.update()), which would
    move the handles of the keys around the take, so theirs are put back as they were."""
    lo = min(s[0] for s in samples) - 1e-4
    hi = max(s[0] for s in samples) + 1e-4
    channels = (("location", 1), (rotation_path, 2))
    data = obj.animation_data
    fcurves = object_fcurves(obj) if data is not None and data.action is not None else None
    kept = {}
    for path, slot in channels:
        for index in range(len(samples[0][slot])):
            fc = fcurves.find(path, index=index) if fcurves is not None else None
            if fc is not None:
                kept[(path, index)] = [key_state(p) for p in fc.keyframe_points if not lo <= p.co.x <= hi]
            else:  # makes the action, its slot and the F-curves as Blender does (a key inside the range)
                obj.keyframe_insert(path, frame=samples[0][0])
                fcurves = object_fcurves(obj)
    for path, slot in channels:
        for index in range(len(samples[0][slot])):
            fc = fcurves.find(path, index=index)
            points = fc.keyframe_points
            for k in reversed(range(len(points))):
                if lo <= points[k].co.x <= hi:
                    points.remove(points[k], fast=True)
            for s in samples:
                points.insert(s[0], s[slot][index], options={"FAST"})
            fc.update()
            outside = [p for p in points if not lo <= p.co.x <= hi]
            before = kept.get((path, index), [])
            if len(outside) != len(before):  # keys made by keyframe_insert above lie inside the range
                raise RuntimeError(f"{path}[{index}]: {len(before)} keys outside frames {lo:.4g}..{hi:.4g} "
                                   f"became {len(outside)}")
            for p, state in zip(outside, before):
                _put_back(p, state)


def _put_back(point, state):
    co, left, right = state[:3]
    for name, value in zip(_KEY_FIELDS, state[3:]):
        if getattr(point, name) != value:
            setattr(point, name, value)
    point.co = co
    point.handle_left = left
    point.handle_right = right


def object_fcurves(obj):
    """The F-curves animating the object: on the action up to Blender 4.x, in the action slot's
    channel bag from 4.4 (only there in 5.0)."""
    data = obj.animation_data
    if hasattr(data.action, "fcurves"):
        return data.action.fcurves
    from bpy_extras import anim_utils

    return anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot).fcurves
