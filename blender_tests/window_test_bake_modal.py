# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): the Bake operator invoked
from the UI runs modal, its timer keeps the UI live and updates the progress props while the
worker bakes, a simulated Esc cancels with the complete frames kept, and Resume finishes the
sequence. Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import os
import tempfile
import time

import bpy

from support import (BakePacer, check, clear_objects, cube, drive, fail, finish, frames_on_disk as frames_in, invoke,
                     key_locations, remove_on_exit, set_roles, settings, uv_sphere)

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)

FRAMES = 40
TMP = remove_on_exit(tempfile.mkdtemp(prefix="hf_blender_modal_"))
CACHE = os.path.join(TMP, "cache")
state = {"phase": "start", "t0": time.time(), "ticks_while_baking": 0, "cancelled_at": None}


def setup():
    hapticfluid_blender.register()
    scene = clear_objects()
    domain = cube(1.0, (0.5, 0.5, 0.5))
    probe = uv_sphere(0.12, (0.3, 0.5, 0.55))
    key_locations(probe, ((1, (0.3, 0.5, 0.55)), (FRAMES, (0.65, 0.5, 0.55))))
    s = set_roles(scene, domain, probe)
    s.resolution, s.frame_start, s.frame_end, s.substeps = 24, 1, FRAMES, 2
    s.cache_dir = CACHE


def frames_on_disk():
    return frames_in(CACHE)


def step():
    s = settings()
    phase = state["phase"]
    pacer.tick()  # the bake's next frame may start (support.BakePacer)
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
            state["phase"] = "cancelling"  # still paced: released, the bake could end before the Esc is read
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
            pacer.release()  # Resume bakes at its own pace
            check(invoke(bpy.ops.hapticfluid.bake_resume) == {"RUNNING_MODAL"}, "Resume runs modal")
            state["phase"] = "resuming"
    elif phase == "resuming":
        if not s.is_baking:
            check("finished" in s.status, f"Resume finished the bake: '{s.status}'")
            check(len(frames_on_disk()) == FRAMES, f"all {FRAMES} frames are on disk")
            check(s.volume_object is not None and s.volume_object.data.frame_duration == FRAMES,
                  "the Volume object shows the whole sequence")
            hapticfluid_blender.unregister()
            finish("blender modal bake test passed")
            return None
    return 0.1


setup()
pacer = BakePacer()  # the bake outlasts the timer's ticks, however fast it is
drive(step, 240, lambda: f"in phase {state['phase']} (status: {settings().status})")
