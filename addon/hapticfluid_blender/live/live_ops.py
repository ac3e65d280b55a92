# SPDX-License-Identifier: GPL-3.0-or-later
"""Start, Stop and Record operators of the live session, and the ways a session ends.

Start (invoked from the UI) is modal: an event timer on Blender's main thread calls
``LiveController.tick()`` ~40 times a second; Esc, or a right-click in a 3D viewport, or Stop ends
it. Every session is also in ``_RUNNING`` so that opening another file (load_pre), disabling the
add-on (unregister), quitting Blender (atexit) or Stop from a script ends it: force down through
the slew limit, threads joined, draw handlers removed. After a disable, Start refuses for a moment
(modal_guard: Blender 4.3 crashed in modal_handler_add). Run from a script (execute), Start starts
the session and a ``bpy.app.timers`` ticker drives it (headless tests call ``tick()`` directly).
"""

import atexit
import logging

import bpy

from . import live_session
from ..operators import modal_guard

log = logging.getLogger(__name__)

TICK_S = 1.0 / 40.0     # main-thread update period (s)

_RUNNING = []           # [_Run]: the live sessions of this Blender, at most one per scene
_KEPT_DRAWERS = []      # drawers of stopped sessions still showing their last frame


class _Run:
    """A controller, its drawer and whatever ticks it (modal timer or app timer)."""

    def __init__(self, controller, drawer):
        self.controller = controller
        self.drawer = drawer
        self.timer = None       # (window_manager, timer) of a modal operator
        self.app_timer = None   # function registered with bpy.app.timers

    def end(self, reason=None, keep_drawing=False, disabling=False):
        """Stops the session. keep_drawing: the last frame stays drawn (without the force arrow)
        until the next Start, a file load or the add-on's unregister. disabling: the add-on is
        being disabled, so a modal Start's timer goes to modal_guard (Blender 4.3's crash)."""
        report = self.controller.stop(reason)
        if self.drawer is not None:
            if keep_drawing:
                self.drawer.set_force(self.controller.force_origin, (0.0, 0.0, 0.0), self.controller.plan.max_force)
                _KEPT_DRAWERS.append(self.drawer)
            else:
                self.drawer.remove()
        if self.timer is not None:
            wm, timer = self.timer
            if disabling:
                modal_guard.keep_ticking(timer)
            else:
                try:
                    wm.event_timer_remove(timer)
                except (ReferenceError, ValueError):
                    pass
            self.timer = None
        if self.app_timer is not None and bpy.app.timers.is_registered(self.app_timer):
            bpy.app.timers.unregister(self.app_timer)
        if self in _RUNNING:
            _RUNNING.remove(self)
        return report


def _make_drawer():
    if bpy.app.background:
        return None
    try:
        from . import live_draw
    except ImportError as exc:  # drawing is optional: the session still runs
        log.warning("hapticfluid: no viewport drawing (%s)", exc)
        return None
    drawer = live_draw.LiveDrawer()
    drawer.add()
    return drawer


def run_for(scene):
    """The running session of this scene, or None."""
    for run in _RUNNING:
        run.controller.refresh_references()  # after an undo
        try:
            if run.controller.scene == scene:
                return run
        except ReferenceError:
            continue
    return None


def start(scene):
    """Starts a live session for the scene (main thread); returns its _Run. Raises
    live_session.SessionError (fix first) for a bad setup."""
    if run_for(scene) is not None:
        raise live_session.SessionError("Stop the running live session first: this scene already has one")
    clear_kept_drawings()
    drawer = _make_drawer()
    try:
        controller = live_session.LiveController(scene, drawer=drawer)
    except Exception:
        if drawer is not None:
            drawer.remove()
        raise
    scene.hapticfluid_live.status = "starting..."
    run = _Run(controller, drawer)
    _RUNNING.append(run)
    return run


def tick(run):
    """One update of a run; ends it (its last frame stays drawn) when its controller stopped.
    Returns the controller's state."""
    state = run.controller.tick()
    if state == "stopped":
        run.end(keep_drawing=True)
    return state


def clear_kept_drawings():
    while _KEPT_DRAWERS:
        _KEPT_DRAWERS.pop().remove()


def stop_all(reason=None, disabling=False):
    """Ends every live session and removes every drawing; returns their reports (None for a
    clean stop). disabling: see _Run.end."""
    reports = [run.end(reason, disabling=disabling) for run in list(_RUNNING)]
    clear_kept_drawings()
    return reports


@bpy.app.handlers.persistent
def stop_on_load(_filepath=None):
    """load_pre: no session survives its file."""
    for report in stop_all("Start the live session again in this file: opening another file stopped it"):
        if report:
            log.info("hapticfluid: %s", report)


def _stop_at_exit():
    """Quitting: Blender's data may already be gone, so end the engines without touching bpy
    (hapticfluid's own atexit hook would stop the sessions too, after this one)."""
    for run in list(_RUNNING):
        run.controller.engine.close()
    _RUNNING.clear()


atexit.register(_stop_at_exit)


def _in_3d_view(context, event):
    for area in context.window.screen.areas if context.window else ():
        if area.type != "VIEW_3D":
            continue
        for region in area.regions:
            if region.type == "WINDOW" and region.x <= event.mouse_x < region.x + region.width \
                    and region.y <= event.mouse_y < region.y + region.height:
                return True
    return False


class HAPTICFLUID_OT_live_start(bpy.types.Operator):
    """Start the live session: the probe touches the smoke, drawn in the viewport (Esc or right-click stops)"""

    bl_idname = "hapticfluid.live_start"
    bl_label = "Start"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        live = getattr(context.scene, "hapticfluid_live", None)
        return live is not None and run_for(context.scene) is None

    def _start(self, context):
        try:
            run = start(context.scene)
        except live_session.SessionError as exc:
            context.scene.hapticfluid_live.status = str(exc)
            self.report({"ERROR"}, str(exc))
            return None
        if context.scene.hapticfluid_live.device == "TIMELINE" and context.screen is not None \
                and not context.screen.is_animation_playing and not bpy.app.background:
            bpy.ops.screen.animation_play()
        return run

    def execute(self, context):
        run = self._start(context)
        if run is None:
            return {"CANCELLED"}

        def ticker():
            if run not in _RUNNING:
                return None
            return TICK_S if tick(run) != "stopped" else None

        run.app_timer = ticker
        bpy.app.timers.register(ticker, first_interval=TICK_S)
        return {"FINISHED"}

    def invoke(self, context, _event):
        live = context.scene.hapticfluid_live
        if live.allow_unsafe_gain and not live.auto_force_gain:  # say what it risks first; OK runs execute()
            return context.window_manager.invoke_props_dialog(self, width=420)
        if modal_guard.pending():
            message = modal_guard.REFUSAL.format(what="live session or bake")
            context.scene.hapticfluid_live.status = message
            self.report({"ERROR"}, message)
            return {"CANCELLED"}
        self._run = self._start(context)
        if self._run is None:
            return {"CANCELLED"}
        wm = context.window_manager
        self._run.timer = (wm, wm.event_timer_add(TICK_S, window=context.window))
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def draw(self, context):
        live = context.scene.hapticfluid_live
        col = self.layout.column()
        col.label(text=f"Unsafe: Force Gain {live.force_gain:.3g} may be above what the device renders passively.",
                  icon="ERROR")
        col.label(text="The rendering may then put energy into your hand: oscillation, or a kick")
        col.label(text="when the probe meets the fluid's push. Hold the grip firmly; Stop in the sidebar ends it.")
        col.label(text="OK starts the session; to stay safe, turn on Derive Gain instead.")

    def modal(self, context, event):
        run = self._run
        if run not in _RUNNING:  # ended elsewhere (Stop, file load, add-on disabled)
            return self._finish(run)
        if event.value == "PRESS" and (event.type == "ESC" or (event.type == "RIGHTMOUSE"
                                                               and _in_3d_view(context, event))):
            run.end(keep_drawing=True)
            return self._finish(run)
        if event.type == "TIMER":  # ours or another's: an extra tick is harmless
            if tick(run) == "stopped":
                return self._finish(run)
        return {"PASS_THROUGH"}

    def _finish(self, run):
        report = run.controller.report
        if report:
            self.report({"ERROR"}, report)
        else:
            self.report({"INFO"}, "live session stopped")
        return {"FINISHED"} if not report else {"CANCELLED"}


class HAPTICFLUID_OT_live_stop(bpy.types.Operator):
    """Stop the live session: the force ramps down, the threads stop, the last frame stays drawn"""

    bl_idname = "hapticfluid.live_stop"
    bl_label = "Stop"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        return run_for(context.scene) is not None

    def execute(self, context):
        run = run_for(context.scene)
        report = run.end(keep_drawing=True)
        if report:
            self.report({"ERROR"}, report)
        return {"FINISHED"}


class HAPTICFLUID_OT_live_record(bpy.types.Operator):
    """Record the probe's motion as location and rotation keys at the Key Rate (press again to finish); the keys in
    the recorded frames are replaced, all others stay as they were. While the timeline plays it punches in: the
    existing motion plays until Record (frame A), from there Mouse and Falcon drive the probe until Record again
    (frame B, keyed too). Timeline mode re-records the motion as it plays (the pose the fluid's probe followed, at
    the frames played). One undo restores the old keys"""

    bl_idname = "hapticfluid.live_record"
    bl_label = "Record"
    # No UNDO flag: Record-off pushes its own two undo steps, one before the keys change (the
    # channels punched in unmuted) and one after, so one undo restores the old keys.
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context):
        run = run_for(context.scene)
        return run is not None and run.controller.state == "running"

    def execute(self, context):
        controller = run_for(context.scene).controller
        if controller.recording is not None:
            n = controller.stop_recording(before_write=lambda: _undo_push("Before Record"))
            if n:
                _undo_push("Record")
                a, b, looped = controller.last_take
                self.report({"INFO"}, f"recorded {n} key(s) of the probe's motion, frames {a:g}-{b:g}"
                                      + (" (the timeline looped: the take ends at its end frame)" if looped else ""))
            else:
                self.report({"WARNING"}, "Play the timeline (Space) while recording: no frame was played, nothing "
                                         "was keyed" if controller.plan.mode == "TIMELINE" else
                                         "Move the probe while recording: nothing was performed to key")
            return {"FINISHED"}
        try:
            controller.start_recording()
        except live_session.SessionError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        r = controller.recording
        if controller.plan.mode == "TIMELINE" and not controller.timeline_playing():
            self.report({"WARNING"}, "Play the timeline (Space): in Timeline mode Record keys the frames as they play")
        elif r.frame_locked and r.muted:
            self.report({"INFO"}, f"punch-in from frame {r.start_frame:g}: the probe follows you until Record again")
        return {"FINISHED"}


def _undo_push(message):
    """An undo step of the current state (main thread, from an operator)."""
    try:
        bpy.ops.ed.undo_push(message=message)
    except RuntimeError as exc:  # no undo stack (e.g. a script run without a window manager)
        log.info("hapticfluid: no undo step for %s (%s)", message, exc)


classes = (HAPTICFLUID_OT_live_start, HAPTICFLUID_OT_live_stop, HAPTICFLUID_OT_live_record)


def register():
    if stop_on_load not in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.append(stop_on_load)


def unregister():
    stop_all("Enable the add-on and start the session again: disabling the add-on stopped it", disabling=True)
    if stop_on_load in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(stop_on_load)
    if not bpy.app.background:
        try:
            from . import live_draw
        except ImportError:
            return
        live_draw.remove_all()
