# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): disabling the add-on while a
live session runs modal (Start invoked from the 3D view) ends the session and its threads;
enabling it again and invoking Start (or Bake) at once is refused ("Try again in a moment") until
Blender has dropped the ended session's modal handler, and a Start a moment later runs modal and
ticks. Blender 4.3 segfaulted in modal_handler_add on that immediate Start (a window still listed
the handler of the operator whose class unregister freed; see modal_guard.py); 3.4 did not.
Exits 0 when every check passed, 1 otherwise (os._exit: a timer cannot raise out)."""

import threading
import time

import bpy

from support import check, drive, fail, finish, invoke, live_scene

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.live import live_ops  # noqa: E402
from hapticfluid_blender.operators import modal_guard  # noqa: E402

state = {"phase": "start", "phase_t": time.time()}


def refused(op):
    """Invoke `op` from the 3D view; True when it refused with the moment-later message (an error
    report, which the call raises)."""
    try:
        invoke(op)
    except RuntimeError as exc:
        return "Try again in a moment" in str(exc)
    return False


def live_ticks(min_ticks):
    run = live_ops.run_for(bpy.context.scene)
    return run is not None and run.controller.state == "running" and run.controller.ticks >= min_ticks


def next_phase(name):
    state.update(phase=name, phase_t=time.time())


def first_start(_elapsed):
    check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "Start invoked from the 3D view runs modal")
    next_phase("disable")
    return 0.1


def disable_and_enable(elapsed):
    if not live_ticks(5):
        if elapsed > 60:
            fail(f"the session did not tick: {bpy.context.scene.hapticfluid_live.status}")
        return 0.1
    hapticfluid_blender.unregister()
    threads = [t.name for t in threading.enumerate() if t.name.startswith("hapticfluid-live")]
    check(live_ops.run_for(bpy.context.scene) is None and not threads,
          f"disabling the add-on ended the session and its threads ({threads})")
    hapticfluid_blender.register()
    # Blender 4.3 crashed on this Start: the ended session's handler was still listed
    check(refused(bpy.ops.hapticfluid.live_start), "Start right after enabling again is refused")
    check(refused(bpy.ops.hapticfluid.bake), "Bake right after enabling again is refused too")
    check(live_ops.run_for(bpy.context.scene) is None, "no session was started")
    next_phase("start_later")
    return modal_guard.DROP_S + 0.1


def start_later(elapsed):
    try:
        result = invoke(bpy.ops.hapticfluid.live_start)
    except RuntimeError as exc:  # Blender's timers may run a little early: a few more tries
        if "Try again in a moment" in str(exc) and elapsed < 4 * modal_guard.DROP_S:
            return 0.2
        raise
    check(result == {"RUNNING_MODAL"}, f"Start runs modal {elapsed:.1f} s after the refusals")
    next_phase("ticking")
    return 0.1


def ticking(elapsed):
    if live_ticks(5):
        check(bpy.ops.hapticfluid.live_stop() == {"FINISHED"}, "the new session ticks, and Stop ends it")
        next_phase("end")
    elif elapsed > 60:
        fail(f"the new session did not tick: {bpy.context.scene.hapticfluid_live.status}")
    return 0.1


def end(elapsed):
    if elapsed < 0.5:  # the modal operator sees its session gone and finishes first
        return 0.1
    hapticfluid_blender.unregister()
    finish("blender live disable test passed")
    return None


PHASES = {"start": first_start, "disable": disable_and_enable, "start_later": start_later, "ticking": ticking,
          "end": end}


def step():
    return PHASES[state["phase"]](time.time() - state["phase_t"])


hapticfluid_blender.register()
live_scene()
drive(step, 300, lambda: f"in phase {state['phase']} (status: {bpy.context.scene.hapticfluid_live.status})")
