# SPDX-License-Identifier: GPL-3.0-or-later
"""What the live tests that play the timeline share (imported by test_live_record_punch_in.py and
test_live_feel_playback.py; not a test itself): the scene, a session started on it, the timeline
played frame after frame as Blender's playback would, Record pressed, the keys read back.

There is no playback without a window, so play() plays the timeline itself: scene.frame_set()
frame after frame at FPS frames a second of wall time, a tick after each, with the controller
told that the timeline plays (controller.timeline_playing)."""

import math
import time

import bpy

from support import check, cube, empty_file, set_roles, uv_sphere

from hapticfluid_blender.live import live_ops, recording  # noqa: E402  (support put the add-on on sys.path)

FPS = 24
CENTRE = (0.5, 0.5, 0.5)
CHANNELS = ("location", "rotation_euler")


def new_scene(device, gesture="REST", source=False):
    """A 1 m domain cube (corner at the origin), a sphere probe at its centre (and a smoke source
    at its floor), 16^3, 24 fps."""
    scene = empty_file()
    domain = cube(1.0, CENTRE, "Domain")
    probe = uv_sphere(0.08, CENTRE, "Probe")
    smoke = uv_sphere(0.08, (0.5, 0.5, 0.15), "Source") if source else None
    bake = set_roles(scene, domain, probe, smoke)
    bake.probe_shape = "SPHERE"
    bake.pressure_iterations = 10
    live = scene.hapticfluid_live
    live.auto_resolution = False
    live.resolution = 16
    live.device = device
    live.hand_gesture = gesture
    live.record_rate = FPS
    scene.render.fps, scene.render.fps_base = FPS, 1.0
    scene.frame_start, scene.frame_end = 1, 60
    bpy.context.view_layer.update()
    return scene, probe


def start(scene, warm_s=0.0, still_while_warming=False):
    """A live session started and ticked for warm_s s of wall time (the simulated hand homes);
    the controller is then told the timeline plays (play() plays it). still_while_warming: the
    timeline is still while the hand homes (a guided hand is not pulled along meanwhile)."""
    run = live_ops.start(scene)
    run.controller.wait_started()
    run.controller.timeline_playing = lambda: not still_while_warming
    end = time.monotonic() + warm_s
    while time.monotonic() < end:
        live_ops.tick(run)
        time.sleep(live_ops.TICK_S)
    run.controller.timeline_playing = lambda: True  # the test plays the timeline (play())
    return run


def play(run, frames, each=None):
    """Shows each frame for 1/FPS s of wall time, ticking as Blender's timers would."""
    scene = run.controller.scene
    for frame in frames:
        t = time.monotonic()
        scene.frame_set(frame)
        if live_ops.tick(run) == "stopped":
            raise AssertionError(f"the session stopped: {run.controller.report}")
        if each is not None:
            each(frame)
        time.sleep(max(0.0, 1.0 / FPS - (time.monotonic() - t)))


def record():
    check(bpy.ops.hapticfluid.live_record() == {"FINISHED"}, "Record runs")


def keys(probe):
    """{(path, index): [key_state, ...]} of the probe's location and rotation F-curves."""
    fcurves = recording.object_fcurves(probe)
    out = {}
    for fc in fcurves:
        if fc.data_path in CHANNELS:
            out[(fc.data_path, fc.array_index)] = [recording.key_state(p) for p in fc.keyframe_points]
    return out


def record_frames_1_to_48(scene, still_while_warming=False):
    """The Falcon's gesture performed and recorded over frames 1-48, played at FPS: a session
    past its 0.6 s homing gesture, Record at frame 1 and again at 48, the session stopped."""
    run = start(scene, warm_s=1.0, still_while_warming=still_while_warming)
    scene.frame_set(1)
    live_ops.tick(run)
    record()
    play(run, range(2, 49))
    record()
    live_ops.stop_all()


def distance_to_polyline(p, points):
    best = math.inf
    for a, b in zip(points, points[1:] or points):
        ab = [b[i] - a[i] for i in range(3)]
        n = sum(c * c for c in ab)
        w = 0.0 if n == 0.0 else max(0.0, min(1.0, sum((p[i] - a[i]) * ab[i] for i in range(3)) / n))
        best = min(best, math.dist(p, [a[i] + w * ab[i] for i in range(3)]))
    return best
