# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run (--enable-event-simulate): Record in Timeline mode with
Blender's own playback (the headless test, test_live_record_punch_in.py, plays frames itself).

The probe's keys move it around a 0.2 m circle (one turn in 48 frames, a key every 4 frames).
Start, invoked from the 3D view in Timeline mode, runs modal and starts playback; Record at a frame
A once the session runs, Record again 12 or more frames later (B). Checks: the controller sees the
playback (timeline_playing), the take is frame-locked and covers exactly the frames A..B that
played, one key per frame played (the record rate is the scene's 24 fps), each key the pose
played at its frame and within 2 mm of the circle, the keys outside A..B unchanged to the bit.
Prints the frames played per second of wall time (the viewport's pace: playback shows every
frame). Exits 0 when every check passed, 1 otherwise."""

import math
import time

import bpy

from support import check, drive, fail, invoke, live_scene, settings

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.live import live_ops, recording  # noqa: E402

CENTRE = (0.5, 0.5, 0.5)
RADIUS_M = 0.1
FRAMES_RECORDED = 12
state = {"phase": "start", "phase_t": time.time()}


def setup():
    hapticfluid_blender.register()
    scene = live_scene()
    scene.hapticfluid_live.device = "TIMELINE"
    scene.hapticfluid_live.record_rate = 24.0
    scene.render.fps, scene.render.fps_base = 24, 1.0
    scene.frame_start, scene.frame_end = 1, 250
    scene.sync_mode = "NONE"  # play every frame: a slow viewport slows the timeline, no frame dropped
    probe = settings(scene).probe
    for frame in range(-47, 300, 4):  # from before the frame range: no end key's flat handle in it
        a = 2.0 * math.pi * (frame - 1) / 48.0
        probe.location = (CENTRE[0] + RADIUS_M * math.cos(a), CENTRE[1] + RADIUS_M * math.sin(a), CENTRE[2])
        probe.keyframe_insert("location", frame=frame)
    scene.frame_set(1)
    state["old"] = keys(probe)
    fcurves = recording.object_fcurves(probe)
    state["played"] = {f: tuple(fcurves.find("location", index=i).evaluate(f) for i in range(3)) for f in range(1, 251)}


def keys(probe):
    fcurves = recording.object_fcurves(probe)
    return {(fc.data_path, fc.array_index): [recording.key_state(p) for p in fc.keyframe_points]
            for fc in fcurves if fc.data_path in ("location", "rotation_euler")}


def next_phase(name):
    state["phase"] = name
    state["phase_t"] = time.time()


def step():
    scene = bpy.context.scene
    live = scene.hapticfluid_live
    run = live_ops.run_for(scene)
    phase = state["phase"]
    if phase == "start":
        check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, "Start invoked in Timeline mode runs modal")
        next_phase("running")
    elif phase == "running":
        if run is None:
            fail(f"the session ended: {live.status}")
        if run.controller.state == "running" and scene.frame_current >= 3:
            check(run.controller.timeline_playing(), "the controller sees Blender's playback")
            check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and live.is_recording, "Record starts")
            check(run.controller.recording.frame_locked, "... locked to the frames played")
            state["a"], state["t"] = scene.frame_current, time.time()
            next_phase("recording")
    elif phase == "recording":
        if run is None:
            fail(f"the session ended: {live.status}")
        if scene.frame_current >= state["a"] + FRAMES_RECORDED:
            b = scene.frame_current
            seconds = time.time() - state["t"]
            check(bpy.ops.hapticfluid.live_record() == {"FINISHED"} and not live.is_recording, "Record ends")
            a_key, b_key, looped = run.controller.last_take
            check((a_key, b_key, looped) == (float(state["a"]), float(b), False),
                  f"the take covers the frames played, {state['a']}-{b} ({run.controller.last_take})")
            probe = settings(scene).probe
            fcurves = recording.object_fcurves(probe)
            columns = [{p.co.x: p.co.y for p in fcurves.find("location", index=i).keyframe_points} for i in range(3)]
            frames = [f for f in sorted(columns[0]) if a_key <= f <= b_key]
            taken = [tuple(columns[i][f] for i in range(3)) for f in frames]
            to_circle = max(abs(math.dist(p[:2], CENTRE[:2]) - RADIUS_M) + abs(p[2] - CENTRE[2]) for p in taken)
            to_played = max(math.dist(p, state["played"][int(f)]) for f, p in zip(frames, taken))
            print(f"MEASURED Timeline Record in a window: frames {state['a']}-{b} played in {seconds:.1f} s "
                  f"({(b - state['a']) / seconds:.2f} frames/s of wall time, load average "
                  f"{__import__('os').getloadavg()[0]:.1f}); {len(taken)} keys, 24 per second of played motion; "
                  f"farthest from the pose played at its frame {1e3 * to_played:.4f} mm, from the circle "
                  f"{1e3 * to_circle:.3f} mm", flush=True)
            check(len(taken) == b - state["a"] + 1 and frames == [float(f) for f in range(state["a"], b + 1)],
                  f"one key per frame played ({len(taken)})")
            check(to_played <= 1e-6, f"each key is the pose played at its frame ({1e3 * to_played:.4f} mm)")
            check(to_circle <= 0.002, f"every key within 2 mm of the circle ({1e3 * to_circle:.3f} mm)")
            after = keys(probe)
            for channel, states in state["old"].items():
                outside = [s for s in states if not a_key - 1e-3 <= s[0][0] <= b_key + 1e-3]
                if outside != [s for s in after[channel] if not a_key - 1e-3 <= s[0][0] <= b_key + 1e-3]:
                    fail(f"{channel}: keys outside {a_key}-{b_key} changed")
            check(True, "the keys outside the take are unchanged to the bit")
            check(bpy.ops.hapticfluid.live_stop() == {"FINISHED"}, "Stop runs")
            print("blender live Timeline Record window test passed", flush=True)
            bpy.ops.wm.quit_blender()
            return None
    return 0.1


setup()
drive(step, 400, lambda: f"in phase {state['phase']} at frame {bpy.context.scene.frame_current} "
                         f"(status: {bpy.context.scene.hapticfluid_live.status})")
