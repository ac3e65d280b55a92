"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): the Bake operator invoked
from the UI runs modal, its timer keeps the UI live and updates the progress props while the
worker bakes, a simulated Esc cancels with the complete frames kept, and Resume finishes the
sequence. Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import os
import shutil
import sys
import tempfile
import time
import traceback

import bpy

sys.path.insert(0, os.path.join(os.environ["HAPTICFLUID_SOURCE_DIR"], "addon"))
import hapticfluid_blender  # noqa: E402

FRAMES = 40
TMP = tempfile.mkdtemp(prefix="hf_blender_modal_")
CACHE = os.path.join(TMP, "cache")
state = {"phase": "start", "t0": time.time(), "ticks_while_baking": 0, "cancelled_at": None}


def fail(message):
    print("FAILED:", message, flush=True)
    shutil.rmtree(TMP, ignore_errors=True)
    os._exit(1)


def check(condition, message):
    if not condition:
        fail(message)
    print("ok:", message, flush=True)


def setup():
    hapticfluid_blender.register()
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.5, 0.5, 0.5))
    domain = bpy.context.active_object
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.12, location=(0.3, 0.5, 0.55))
    probe = bpy.context.active_object
    probe.keyframe_insert("location", frame=1)
    probe.location = (0.65, 0.5, 0.55)
    probe.keyframe_insert("location", frame=FRAMES)
    s = scene.hapticfluid_bake
    s.domain, s.probe = domain, probe
    s.resolution, s.frame_start, s.frame_end, s.substeps = 24, 1, FRAMES, 2
    s.cache_dir = CACHE


def invoke(op):
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    with bpy.context.temp_override(window=win, area=area):
        return op("INVOKE_DEFAULT")


def frames_on_disk():
    folder = os.path.join(CACHE, "data")
    return sorted(os.listdir(folder)) if os.path.isdir(folder) else []


def tick():
    try:
        return step()
    except Exception:
        traceback.print_exc()
        fail("exception in the test timer")


def step():
    s = bpy.context.scene.hapticfluid_bake
    if time.time() - state["t0"] > 240:
        fail(f"timed out in phase {state['phase']} (status: {s.status})")
    phase = state["phase"]
    if phase == "start":
        check(invoke(bpy.ops.hapticfluid.bake) == {"RUNNING_MODAL"}, "Bake invoked from the UI runs modal")
        check(s.is_baking, "the scene says a bake is running")
        state["phase"] = "baking"
    elif phase == "baking":
        if s.is_baking:
            state["ticks_while_baking"] += 1
        if s.progress >= 0.1 and s.is_baking:
            check(s.status.startswith("frame "), f"the modal timer copies progress into the props: '{s.status}'")
            win = bpy.context.window_manager.windows[0]
            win.event_simulate(type="ESC", value="PRESS")
            state["phase"] = "cancelling"
        elif not s.is_baking:
            fail(f"the bake ended before Esc could be sent: {s.status}")
    elif phase == "cancelling":
        if s.is_baking:
            state["ticks_while_baking"] += 1
        else:
            check(state["ticks_while_baking"] >= 2, f"the UI stayed live during the bake "
                                                    f"({state['ticks_while_baking']} timer ticks)")
            check("cancelled" in s.status, f"Esc cancelled the bake: '{s.status}'")
            done = frames_on_disk()
            check(0 < len(done) < FRAMES, f"complete frames are kept after cancelling ({len(done)})")
            check(not any(n.endswith(".tmp") for n in os.listdir(os.path.join(CACHE, "data"))),
                  "no temporary file is left")
            state["cancelled_at"] = len(done)
            check(invoke(bpy.ops.hapticfluid.bake_resume) == {"RUNNING_MODAL"}, "Resume runs modal")
            state["phase"] = "resuming"
    elif phase == "resuming":
        if not s.is_baking:
            check("finished" in s.status, f"Resume finished the bake: '{s.status}'")
            check(len(frames_on_disk()) == FRAMES, f"all {FRAMES} frames are on disk")
            check(s.volume_object is not None and s.volume_object.data.frame_duration == FRAMES,
                  "the Volume object shows the whole sequence")
            hapticfluid_blender.unregister()
            shutil.rmtree(TMP, ignore_errors=True)
            print("blender modal bake test passed", flush=True)
            bpy.ops.wm.quit_blender()
            return None
    return 0.1


setup()
bpy.app.timers.register(tick, first_interval=1.0)
