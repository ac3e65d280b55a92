"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): the live session's Start
operator invoked from the 3D view runs modal on the simulated Falcon, its event timer ticks the
controller (stats and snapshots arrive, the UI stays live), Record keys the probe, a simulated Esc
stops it; a Mouse-mode session stops on a right-click in the viewport, a third on the Stop
operator; quitting with a fourth running exits cleanly. Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import os
import sys
import threading
import time
import traceback

import bpy

sys.path.insert(0, os.path.join(os.environ["HAPTICFLUID_SOURCE_DIR"], "addon"))
import hapticfluid_blender  # noqa: E402
from hapticfluid_blender import live_ops  # noqa: E402

try:
    from hapticfluid_blender import live_draw  # noqa: F401  (the viewport drawing, when present)

    HAS_DRAW = True
except ImportError:
    HAS_DRAW = False
state = {"phase": "start", "t0": time.time(), "phase_t": time.time(), "ticks": 0}


def fail(message):
    print("FAILED:", message, flush=True)
    os._exit(1)


def check(condition, message):
    if not condition:
        fail(message)
    print("ok:", message, flush=True)


def setup():
    hapticfluid_blender.register()
    scene = bpy.context.scene
    for obj in list(scene.objects):
        if obj.type == "MESH":
            bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    domain = bpy.context.active_object
    domain.display_type = "WIRE"
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.1, location=(0.4, 0.5, 0.5))
    probe = bpy.context.active_object
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.06, location=(0.5, 0.5, 0.12))
    source = bpy.context.active_object
    bake = scene.hapticfluid_bake
    bake.domain, bake.probe, bake.source = domain, probe, source
    bake.pressure_iterations = 20
    live = scene.hapticfluid_live
    live.device = "SIMULATED_FALCON"
    live.auto_resolution = False
    live.resolution = 16


def view3d():
    win = bpy.context.window_manager.windows[0]
    return win, next(a for a in win.screen.areas if a.type == "VIEW_3D")


def invoke(op):
    win, area = view3d()
    with bpy.context.temp_override(window=win, area=area):
        return op("INVOKE_DEFAULT")


def next_phase(name):
    state["phase"] = name
    state["phase_t"] = time.time()


def running():
    return live_ops.run_for(bpy.context.scene)


def ended(phase_name):
    """True once the session is fully gone (no run, no live thread, props cleared)."""
    live = bpy.context.scene.hapticfluid_live
    gone = running() is None and not live.is_running
    if gone:
        threads = [t.name for t in threading.enumerate() if t.name.startswith("hapticfluid-live")]
        check(not threads, f"{phase_name}: no live thread left ({threads})")
    return gone


def tick():
    try:
        return step()
    except Exception:
        traceback.print_exc()
        fail("exception in the test timer")


def step():
    scene = bpy.context.scene
    live = scene.hapticfluid_live
    if time.time() - state["t0"] > 400:
        fail(f"timed out in phase {state['phase']} (status: {live.status})")
    phase = state["phase"]
    elapsed = time.time() - state["phase_t"]
    if phase == "start":
        check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "Start invoked from the 3D view runs modal")
        next_phase("running")
    elif phase == "running":
        run = running()
        if run is None:
            fail(f"the session ended: {live.status}")
        if run.controller.state == "running" and run.controller.ticks >= 10 and run.controller.last_sequence >= 3 \
                and live.sim_rate_hz > 0.0:
            check(True, f"the modal timer ticks the controller ({run.controller.ticks} ticks, snapshot "
                        f"{run.controller.last_sequence})")
            check(live.is_running and live.haptic_rate_hz > 100.0,
                  f"stats arrive: sim {live.sim_rate_hz:.1f} Hz, haptic {live.haptic_rate_hz:.0f} Hz")
            state["ticks"] = run.controller.ticks
            check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and live.is_recording, "Record starts recording")
            next_phase("recording")
    elif phase == "recording":
        recording = running().controller.recording
        if len(recording.samples) >= 5:  # ticks are slow while Xvfb's llvmpipe redraws: count samples
            n = len(recording.samples)
            check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and not live.is_recording, "Record again ends it")
            probe = scene.hapticfluid_bake.probe
            from hapticfluid_blender import live_session

            fc = live_session.object_fcurves(probe).find("location", index=0)
            check(fc is not None and len(fc.keyframe_points) == n, f"one key per recorded tick ({n})")
            win, _area = view3d()
            win.event_simulate(type="ESC", value="PRESS")
            win.event_simulate(type="ESC", value="RELEASE")
            next_phase("esc")
    elif phase == "esc":
        if ended("Esc"):
            check(live.status == "stopped", f"Esc stopped the session cleanly: '{live.status}'")
            if HAS_DRAW:
                kept = live_ops._KEPT_DRAWERS
                check(len(kept) == 1 and kept[0].is_added and kept[0].frames_drawn > 0,
                      "the last frame stays drawn after Stop")
            live.device = "MOUSE"
            check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "a Mouse-mode session starts")
            check(not live_ops._KEPT_DRAWERS, "the next Start replaces the kept drawing")
            next_phase("mouse")
        elif elapsed > 10:
            fail("Esc did not stop the session")
    elif phase == "mouse":
        run = running()
        if run is not None and run.controller.state == "running" and run.controller.ticks >= 5:
            win, area = view3d()
            region = next(r for r in area.regions if r.type == "WINDOW")
            x, y = region.x + region.width // 2, region.y + region.height // 2
            win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
            win.event_simulate(type="RIGHTMOUSE", value="PRESS", x=x, y=y)
            win.event_simulate(type="RIGHTMOUSE", value="RELEASE", x=x, y=y)
            next_phase("rightclick")
        elif run is None:
            fail(f"the Mouse session ended: {live.status}")
    elif phase == "rightclick":
        if ended("right-click"):
            check(live.status == "stopped", "a right-click in the viewport stopped it")
            check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "a third session starts")
            next_phase("stop")
        elif elapsed > 10:
            fail("the right-click did not stop the session")
    elif phase == "stop":
        run = running()
        if run is not None and run.controller.state == "running" and run.controller.ticks >= 3:
            check(bpy.ops.hapticfluid.live_stop() == {"FINISHED"}, "Stop runs")
            check(ended("Stop"), "Stop ended the session at once")
            next_phase("finish")
    elif phase == "finish":
        if elapsed > 0.5:  # the modal operator has seen its session gone and finished
            check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "a last session starts")
            next_phase("quit")
    elif phase == "quit":
        run = running()
        if run is not None and run.controller.state == "running":
            # Quitting with a session running must end it and exit cleanly (exit code 0, no hang:
            # ctest's timeout and exit code judge this part).
            print("blender live modal test passed; quitting with a session running", flush=True)
            bpy.ops.wm.quit_blender()
            return None
    return 0.1


setup()
bpy.app.timers.register(tick, first_interval=1.0)
