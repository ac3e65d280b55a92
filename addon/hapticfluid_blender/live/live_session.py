# SPDX-License-Identifier: GPL-3.0-or-later
"""The live session's controller: a plain class, no drawing and no operator, testable headless.

``LiveController(scene)`` reads everything it needs from bpy on the main thread (``read_plan``),
then a worker thread (which never touches bpy) opens the device, makes the Simulation and the
HapticSession and starts it, so a Falcon's firmware upload or the GL context never freezes
Blender. ``tick()`` runs on the main thread ~30-60 times a second: it pushes the probe object's
pose to the host device (Mouse, Timeline) or moves the object to the device pose (Falcon,
Simulated Falcon), takes the newest field snapshot if its sequence changed, copies the stats
into the scene's live properties and samples the take while recording (recording.py). ``stop()`` ramps the force
down through the session's slew limit, joins the threads and returns a report (or None).

Every bad setup raises (or, found by the worker, ends the session with) a ``SessionError`` whose
message starts with the fix.
"""

import logging
import os
import threading
import time
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Tuple

import bpy

from ..bake import blender_scene
from ..properties import roles
from ..properties.machine import backend_choice
from . import recording

log = logging.getLogger(__name__)

HOST_MODES = ("MOUSE", "TIMELINE")     # the object's transform drives the probe
DEVICE_MODES = ("FALCON", "SIMULATED_FALCON")  # the device drives the object
SNAPSHOT_INTERVAL_S = 1.0 / 60.0       # newest fields for the viewport at most this often (wall s)
STATS_PERIOD_S = 0.25                  # the panel's live figures at most this often (s of the controller's clock)
# Falcon modes keep the device's poses of every haptic period this long (s) for Record: each tick
# takes them, so Record keys the hand's path between ticks however rarely Blender ticks.
TRACE_SECONDS = 5.0
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
    viewport_first: bool = True        # computing on the CPU, the simulation yields the cores to drawing
    backend: str = ""                  # the Preferences' Backend ('auto', 'gpu', 'cpu'; '': the environment's)


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
        feel_playback=live.feel_playback, viewport_first=viewport_first(live.cpu_share, live.device),
        backend=backend_choice(bpy.context))


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


def preview_resolution(on_cpu: bool) -> int:
    """Cells along the longest edge when the resolution is automatic: 32 where the simulation
    computes on the CPU (the CPU backend or llvmpipe, beside Blender's drawing), 64 on a GPU."""
    return 32 if on_cpu else 64


class _Engine:
    """The hapticfluid objects of one session, made on the worker thread (no bpy there)."""

    def __init__(self):
        self.sim = None
        self.device = None
        self.session = None
        self.resolution = None
        self.device_text = ""      # the backend and renderer in use (the stats)
        self.workspace_box = None  # (lo, hi) world m for device modes

    def build(self, plan: LivePlan):
        hf = _import_hf()
        from hapticfluid import assembly

        self.device = self._open_device(hf, plan)
        size = [plan.domain_hi[i] - plan.domain_lo[i] for i in range(3)]
        try:  # the device the simulation will use (HAPTICFLUID_EGL_DEVICE may name a bad one)
            on_cpu = assembly.computes_on_cpu(hf.probe_device(backend=plan.backend))
        except hf.HapticFluidError as exc:
            raise SessionError(_gl_context_problem(exc)) from None
        res = plan.resolution if plan.resolution is not None else preview_resolution(on_cpu)
        share = assembly.live_share(on_cpu, plan.viewport_first)
        session_args = dict(plan.session_args)
        if share.min_sim_dt is not None:
            session_args["min_sim_dt"] = share.min_sim_dt
        try:
            settings = assembly.fluid_settings(plan.domain_lo, size, res, plan.fluid, backend=plan.backend,
                                               thread_niceness=share.thread_niceness)
            session_settings = assembly.session_settings(session_args, plan.auto_workspace)
        except (hf.InvalidArgumentError, TypeError) as exc:
            raise SessionError(_fix_first(str(exc))) from None
        scene = assembly.SceneDescription(
            settings,
            source=None if plan.source is None else assembly.Source(**plan.source),  # held where it is at Start
            probe=assembly.Probe(matrix=plan.probe_matrix, **plan.probe_shape))
        try:
            self.sim, self.session = assembly.build(scene, self.device, session_settings)
        except hf.MeshNotClosedError as exc:  # the source's mesh is checked closed before (source_mesh)
            raise SessionError(f"Close the probe '{plan.probe_name}' mesh (Edit Mode: Mesh > Clean Up > Fill Holes, "
                               f"then Mesh > Normals > Recalculate Outside) or use the Sphere probe shape: "
                               f"{exc}") from None
        except hf.InvalidArgumentError as exc:  # the source, the probe or the session's settings
            raise SessionError(_fix_first(str(exc))) from None
        except hf.HapticFluidError as exc:  # no GL context
            raise SessionError(_gl_context_problem(exc)) from None
        self.resolution = settings.resolution
        device = self.sim.device
        self.device_text = f"{device['backend'].upper()}: {device['renderer']}"
        if plan.mode in DEVICE_MODES:  # where the engine maps the device's workspace
            lo, hi = self.session.workspace_box
            self.workspace_box = (tuple(float(x) for x in lo), tuple(float(x) for x in hi))
        if plan.mode in HOST_MODES:  # the first pose the haptic thread reads is the object's
            matrix = plan.probe_matrix
            self.device.push_pose(tuple(matrix[r][3] for r in range(3)),
                                  orientation=hf.HapticSession.probe_rotation(matrix))
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
        self._stats_written = None  # clock() at the panel's figures' last update (_update_stats)
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
            self.engine.device.push_pose(tuple(m.translation), orientation=session.probe_rotation(m))
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
        live.device_used = self.engine.device_text
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
        curves = recording.object_fcurves(obj)
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
        return recording.object_fcurves(self.probe).find("location", index=0) is not None

    def _take_trace(self):
        """Device modes: the device's poses since the last tick (one per haptic period); while
        recording they become samples of the object's path (Recording.add_trace, at the origins the
        engine put the probe at), so Record keys the hand's path, not the straight line between
        ticks. Needs the controller's clock to be the trace's (time.monotonic, CLOCK_MONOTONIC)."""
        trace = self.session.trace()
        r = self.recording
        if r is None or self.clock is not time.monotonic:
            return
        if r.frame_locked:  # after trace(): every pose it gave is older than this
            r.mark_frame(self.clock(), float(self.scene.frame_current_final))
        if r.looped or not len(trace["time"]):
            return
        r.add_trace(trace["time"], self.session.probe_origin(trace["position"]), self.probe)

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
        """The panel's live figures, at most every STATS_PERIOD_S (the first tick at once), each
        written only where it changed: writing an add-on's property tags its scene for the
        depsgraph and redraws every region of the window (Blender's update of an ID property), so
        40 writes a second of a dozen figures redrew the whole window, not just the viewport."""
        now = self.clock()
        if self._stats_written is not None and now - self._stats_written < STATS_PERIOD_S:
            return
        self._stats_written = now
        s = self.session.stats()
        figures = {
            "sim_rate_hz": s["sim_rate_hz"],
            "haptic_rate_hz": s["haptic_rate_hz"],
            "jitter_p99_ms": s["jitter_p99_ms"],
            "latency_p50_ms": s["latency_p50_ms"],
            "latency_p99_ms": s["latency_p99_ms"],
            "force_n": float(sum(c * c for c in latest["sim_force"]) ** 0.5),
            "device_force_n": float(sum(c * c for c in latest["commanded_force"]) ** 0.5),
            "realtime": bool(s["realtime"]),
            "force_gain_used": s.get("force_gain", 0.0),
            "force_gain_reason": s.get("force_gain_reason", ""),
            "device_state": (f"{self.engine.device.info().name}: {'homed' if latest['homed'] else 'not homed'}, "
                             f"buttons {latest['buttons']:#x}"),
            "scheduling": s["scheduling"],
        }
        live = self.live
        for name, value in figures.items():
            if getattr(live, name) != value:
                setattr(live, name, value)

    # -- recording ------------------------------------------------------------------------
    def start_recording(self):
        """Record on. Frame-locked when the timeline plays (and always in Timeline mode): the take
        starts at the frame playing (A) and its samples belong to the frames played. Mouse and
        Falcon modes then punch in: the probe's location and rotation F-curves are muted until
        Record-off so the performance, not the existing keys, moves the probe."""
        if self.state != "running":
            raise SessionError("Start the live session first: Record keys the motion performed during it")
        now = self.clock()
        locked = self.plan.mode == "TIMELINE" or bool(self.timeline_playing())
        self.recording = recording.Recording.start(self.probe, self.scene, now, self.live.record_rate, locked,
                                                   punch_in=self.plan.mode != "TIMELINE")
        self.live.is_recording = True
        if self.plan.mode in DEVICE_MODES:  # the object played the keys until now: the grip's pose at A
            self._release_guide()  # the probe goes back to the grip, which the guide kept near the keys
            self._follow_device(self.session.latest())
        self._sample(now)

    def _sample(self, now):
        self.recording.sample(now, float(self.scene.frame_current_final), self.probe)

    def stop_recording(self, before_write=None) -> int:
        """Writes the motion performed as keys at the record rate (replacing the keys in their frame
        range, every key outside it left as it was, bit for bit: recording.write_keys); returns the
        number of poses keyed. Each key is the pose at its time on the path performed
        (recording.resample), so keys come at the record rate however often Blender redrew while
        recording. Frame-locked, the take ends with a key at B, the frame played at Record-off, from
        the pose performed there, so the F-curves stay continuous into the keys after B.
        before_write() runs after muted channels are restored and before any key changes (the Record
        operator pushes an undo step there, so one undo restores the old keys)."""
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
            r.sample(self.clock(), float(self.scene.frame_current_final), obj)  # B, unless a tick sampled it
        keys = r.keys(obj)
        if not keys:  # locked and no frame played, or nothing performed: no take
            return 0
        if before_write is not None:
            before_write()
        recording.write_keys(obj, r.rotation_path, keys)
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
