# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: Record in Timeline
mode and punch-in recording (issue 28 item 3, issue 31 item 3).

There is no playback without a window, so the test plays the timeline itself: scene.frame_set()
frame after frame at 24 frames a second of wall time, a tick after each, as Blender's playback
and the modal operator's timer do, with the controller told that the timeline plays
(controller.timeline_playing). Record is the operator, pressed as the user presses it.

1. Timeline mode: Record on and off with the timeline still keys nothing. The probe's keys move
   it around a 0.2 m circle (one turn in 48 frames); Record
   at frame 10, again at 40, with frames 31-40 played two at a time (playback dropping frames).
   The take re-records what played: keys at the record rate (24/s of played motion) from 10 to
   40, each within 2 mm of the circle and on the path played; the keys outside 10-40 unchanged to
   the bit (co, handles, handle types, interpolation); one undo restores the old keys.
2. Punch-in on the simulated Falcon: a motion recorded over frames 1-48 with the Sweep gesture
   (along x), then, in a new session with the Circle gesture, the timeline plays from 1: the
   probe follows the keys to frame 19; Record at 20, again at 30; then it follows the keys again.
   Keys outside 20-30 unchanged to the bit, a key at every frame 20-30 on the path the grip
   performed and on the Circle gesture's circle (not on the sweep's line), a key at 30 (B), the
   F-curves unmuted; one undo (the session still running) restores the recorded 1-48 keys and
   the probe follows them again. Feel Playback is off (the scripted hand ignores the playback;
   test_live_feel_playback.py has it on).
3. Punch-in in Mouse mode: keys 1-48, Record at 10 and 20, the object dragged between frame
   changes: the keys 11-20 hold the dragged poses, the keys outside 10-20 unchanged to the bit.
4. Re-bake after a punch-in: the Sweep 1-48 baked (16^3, with a smoke source), a punch-in 20-30,
   then Resume (the bake's rebake_plan): frames 1-19 the same files, not rewritten (inode,
   mtime, bytes), frames 20-48 re-baked (written again), 21-48 different.
Any failure raises, so Blender exits 1."""

import math
import time

import bpy

from playback import (CENTRE, CHANNELS, FPS, distance_to_polyline, keys, new_scene, play, record,
                      record_frames_1_to_48, start)
from support import check

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid import hand_gestures  # noqa: E402
from hapticfluid_blender.live import live_ops, recording  # noqa: E402

RADIUS_M = 0.1          # the Timeline test's circle (0.2 m across)
PATH_TOLERANCE_M = 0.002


def key_points(probe, lo, hi):
    """[(frame, (x, y, z))] of the location keys with lo <= frame <= hi."""
    fcurves = recording.object_fcurves(probe)
    columns = [{p.co.x: p.co.y for p in fcurves.find("location", index=i).keyframe_points} for i in range(3)]
    return [(f, tuple(columns[i][f] for i in range(3))) for f in sorted(columns[0]) if lo - 1e-6 <= f <= hi + 1e-6]


def unchanged_outside(before, after, lo, hi, what):
    """Every key of `before` outside [lo, hi] is in `after`, identical in every field."""
    compared = 0
    for channel, states in before.items():
        outside_before = [s for s in states if not lo <= s[0][0] <= hi]
        outside_after = [s for s in after[channel] if not lo <= s[0][0] <= hi]
        if outside_before != outside_after:
            for a, b in zip(outside_before, outside_after):
                if a != b:
                    raise AssertionError(f"{what}: {channel} key at frame {a[0][0]} changed: {a} -> {b}")
            raise AssertionError(f"{what}: {channel} has {len(outside_after)} keys outside {lo}-{hi}, "
                                 f"had {len(outside_before)}")
        compared += len(outside_before)
    check(compared > 0, f"{what}: the {compared} keys outside frames {lo:g}-{hi:g} are unchanged to the bit "
                        f"(co, handles, handle types, interpolation)")


def timeline_record_keys_what_plays():
    scene, probe = new_scene("TIMELINE")
    for frame in range(1, 50, 4):  # a circle keyed every 4 frames, Bezier between the keys
        a = 2.0 * math.pi * (frame - 1) / 48.0
        probe.location = (CENTRE[0] + RADIUS_M * math.cos(a), CENTRE[1] + RADIUS_M * math.sin(a), CENTRE[2])
        probe.keyframe_insert("location", frame=frame)
        probe.keyframe_insert("rotation_euler", frame=frame)
    old = keys(probe)
    bpy.ops.ed.undo_push(message="keys made")
    scene.frame_set(1)
    run = start(scene)
    run.controller.timeline_playing = lambda: False  # stopped: Record-on and off with no frame played
    record()
    live_ops.tick(run)
    record()
    check(keys(probe) == old and run.controller.last_take is None,
          "Timeline Record with no frame played keys nothing (and says to play the timeline)")
    run.controller.timeline_playing = lambda: True
    played = {}

    def keep(frame):
        played[frame] = tuple(probe.location)

    play(run, range(1, 10), keep)
    play(run, [10], keep)
    record()
    check(run.controller.recording.frame_locked and not run.controller.recording.muted,
          "Timeline mode records the frames played, its keys not muted (it re-records what plays)")
    play(run, range(11, 31), keep)
    play(run, range(32, 41, 2), keep)  # playback dropping every other frame
    record()
    written = [f for f, _ in key_points(probe, 10, 40)]
    check(written == [float(f) for f in range(10, 41)], "the keys were written at once, by Record-off itself")
    check(run.controller.last_take == (10.0, 40.0, False), f"the take is frames 10-40 ({run.controller.last_take})")
    play(run, range(41, 49), keep)
    sim = run.controller.engine.sim
    centre = [float(c) for c in sim.probe["centre"]]
    live_ops.stop_all()
    check(math.dist(centre, played[48]) < 0.02, f"the fluid's probe followed the played motion ({centre})")

    taken = key_points(probe, 10, 40)
    per_s = (len(taken) - 1) / ((40 - 10) / FPS)
    check([f for f, _ in taken] == [float(f) for f in range(10, 41)] and per_s >= 20.0,
          f"a key at every frame 10-40: {per_s:.1f} keys per second of played motion")
    path = [played[f] for f in sorted(played) if 10 <= f <= 40]
    to_path = max(distance_to_polyline(p, path) for _, p in taken)
    to_circle = max(abs(math.dist(p[:2], CENTRE[:2]) - RADIUS_M) + abs(p[2] - CENTRE[2]) for _, p in taken)
    print(f"MEASURED Timeline Record: {len(taken)} keys over frames 10-40, {per_s:.1f} keys/s of played motion; "
          f"farthest key from the path played {1e3 * to_path:.4f} mm, from the circle {1e3 * to_circle:.3f} mm")
    check(to_path <= 1e-6, f"every key on the path played ({1e3 * to_path:.4f} mm)")
    check(to_circle <= PATH_TOLERANCE_M, f"every key within 2 mm of the circle ({1e3 * to_circle:.3f} mm)")
    for f in range(10, 31):
        if math.dist(dict(taken)[float(f)], played[f]) > 1e-6:
            raise AssertionError(f"the key at frame {f} is not the pose played there")
    check(True, "the keys at frames played one by one hold the poses played")
    unchanged_outside(old, keys(probe), 10 - 1e-3, 40 + 1e-3, "Timeline Record")
    bpy.ops.ed.undo()
    probe = bpy.data.objects["Probe"]
    check(keys(probe) == old, "one undo restores the old keys")


def record_a_sweep_over_frames_1_to_48(source=False):
    scene, probe = new_scene("SIMULATED_FALCON", "SWEEP", source=source)
    record_frames_1_to_48(scene)
    taken = key_points(probe, 1, 48)
    xs = [p[0] for _, p in taken]
    check([f for f, _ in taken] == [float(f) for f in range(1, 49)], f"the sweep keyed at frames 1-48 ({len(taken)})")
    check(max(xs) - min(xs) > 0.2, f"... a sweep along x ({min(xs):.3f} .. {max(xs):.3f} m)")
    return scene, probe


def punch_in_with_the_simulated_falcon():
    scene, probe = record_a_sweep_over_frames_1_to_48()
    old = keys(probe)
    old_y = [p[1] for _, p in key_points(probe, 1, 48)]
    check(max(old_y) - min(old_y) < 0.02, f"the sweep stays on a line along x (y {min(old_y):.4f} .. {max(old_y):.4f})")
    bpy.ops.ed.undo_push(message="sweep recorded")
    live = scene.hapticfluid_live
    live.hand_gesture = "CIRCLE"
    # The scripted hand circles whatever plays: Feel Playback would pull it towards the sweep until
    # A, so the take would start on the sweep (as it should for a user who feels the playback:
    # test_live_feel_playback.py). Off here, the take is the gesture's alone.
    live.feel_playback = False
    run = start(scene, warm_s=1.5)  # homing, then the circle starts 1 s after it
    c = run.controller
    fcurves = recording.object_fcurves(probe)
    off = []

    def follows_the_keys(frame):
        curves = recording.object_fcurves(probe)  # looked up again: an undo re-reads the action
        want = [curves.find("location", index=i).evaluate(frame) for i in range(3)]
        off.append(math.dist(want, probe.location))

    play(run, range(1, 20), follows_the_keys)
    check(max(off) < 1e-6, f"with Record off the probe follows the keys as the timeline plays ({max(off):.2g} m)")
    play(run, [20])
    t20 = time.monotonic()
    record()
    r = c.recording
    check(r.frame_locked and len(r.muted) == 6 and all(fc.mute for fc in fcurves if fc.data_path in CHANNELS),
          "Record at frame 20 punches in: the probe's location and rotation F-curves are muted")
    samples = r.samples  # the path performed (appended to until Record-off)
    play(run, range(21, 31))
    turn_s = time.monotonic() - t20  # the wall time frames 20-30 took: the hand's circle turns by it
    record()
    check(c.last_take == (20.0, 30.0, False), f"the take is frames 20-30 ({c.last_take})")
    check(not any(fc.mute for fc in fcurves), "Record-off unmutes the F-curves")
    off.clear()
    play(run, range(31, 49), follows_the_keys)
    check(max(off) < 1e-6, f"after the take the probe follows the keys again ({max(off):.2g} m)")
    scale = float(c.session.workspace_scale[0])
    after = keys(probe)
    taken = key_points(probe, 20, 30)
    # Ctrl+Z while the session runs: the old keys come back and the session goes on with them.
    bpy.ops.ed.undo()
    probe = bpy.data.objects["Probe"]
    check(keys(probe) == old, "one undo restores the recorded 1-48 keys")
    off.clear()
    play(run, range(1, 6), follows_the_keys)
    check(c.state == "running" and c.probe == probe and max(off) < 1e-6,
          f"the session runs on after the undo, the probe following the restored keys ({max(off):.2g} m)")
    live_ops.stop_all()

    unchanged_outside(old, after, 20 - 1e-3, 30 + 1e-3, "punch-in 20-30")
    check([f for f, _ in taken] == [float(f) for f in range(20, 31)],
          f"a key at every frame 20-30, B included ({len(taken)})")
    path = [s[1] for s in samples]
    to_path = max(distance_to_polyline(p, path) for _, p in taken)
    # The Circle gesture: 25 mm about the workspace's centre, mapped onto the domain at its scale.
    radius = 0.025 * scale
    radii = [math.dist(p[:2], CENTRE[:2]) for _, p in taken]
    angles = [math.degrees(math.atan2(p[1] - CENTRE[1], p[0] - CENTRE[0])) for _, p in taken]
    # Unwrapped (atan2 jumps at +-180 degrees): the sum of the turns from key to key.
    turned = abs(sum((b - a + 180.0) % 360.0 - 180.0 for a, b in zip(angles, angles[1:])))
    # The gesture turns by the hand's clock, which runs with the haptic loop's periods (the wall's):
    # frames 20-30 take 10/24 s when playback keeps pace, longer on a loaded machine.
    expected = 360.0 * turn_s / hand_gestures.CIRCLE_PERIOD_S
    off_line = max(abs(p[1] - CENTRE[1]) for _, p in taken)
    print(f"MEASURED punch-in: {len(taken)} keys over frames 20-30 from {len(samples)} poses performed; farthest "
          f"key from the path performed {1e3 * to_path:.4f} mm; key radius {min(radii):.3f} .. {max(radii):.3f} m "
          f"about the centre (the gesture's circle: {radius:.3f} m), turning {turned:.0f} degrees in {turn_s:.3f} s "
          f"({expected:.0f} expected); up to {off_line:.3f} m off the sweep's line")
    check(len(samples) >= 3 * len(taken), f"the grip's poses between ticks were taken ({len(samples)} poses)")
    check(to_path <= PATH_TOLERANCE_M, f"every key within 2 mm of the path performed ({1e3 * to_path:.4f} mm)")
    # 10 frames of a 4 s turn: 37.5 degrees of the circle when playback keeps pace, far off the
    # sweep's line y = 0.5.
    check(all(abs(rr - radius) < 0.03 for rr in radii) and abs(turned - expected) <= 10.0 + 0.25 * expected
          and off_line > 0.1,
          f"the keys inside follow the Circle gesture (radius {min(radii):.3f} .. {max(radii):.3f} m of "
          f"{radius:.3f}, turning {turned:.0f} degrees in {turn_s:.3f} s: {expected:.0f} expected, "
          f"{off_line:.3f} m off the sweep's line)")


def punch_in_with_the_mouse():
    """Mouse mode: the drag moves the object between frame changes, as mouse events come between
    playback's steps; from Record the muted F-curves leave the dragged pose in place."""
    scene, probe = new_scene("MOUSE")
    for frame, x in ((1, 0.3), (24, 0.7), (48, 0.3)):
        probe.location = (x, 0.5, 0.5)
        probe.keyframe_insert("location", frame=frame)
    old = keys(probe)
    scene.frame_set(1)
    run = start(scene)
    play(run, range(1, 11))
    record()
    check(len(run.controller.recording.muted) == 3, "Record at frame 10 mutes the location curves (no rotation keys)")
    dragged = {}
    for frame in range(11, 21):  # a drag upwards from where the keys left the probe
        probe.location.z += 0.01
        dragged[frame] = tuple(probe.location)
        play(run, [frame])
    record()
    live_ops.stop_all()
    taken = dict(key_points(probe, 10, 20))
    check(sorted(taken) == [float(f) for f in range(10, 21)], f"keys at frames 10-20 ({sorted(taken)})")
    worst = max(math.dist(taken[float(f)], p) for f, p in dragged.items())
    check(worst < 1e-6, f"the keys from 11 on hold the dragged poses, not the old keys ({1e3 * worst:.4f} mm)")
    unchanged_outside(old, keys(probe), 10 - 1e-3, 20 + 1e-3, "Mouse punch-in 10-20")


def rebake_after_a_punch_in():
    """Issue 31 item 3's last step: the recorded 1-48 motion baked, a punch-in 20-30, then one
    press (Resume, which follows hapticfluid.bake.rebake_plan) re-bakes from the checkpoint
    before frame 20: frames 1-19 are the same files (inode, mtime, bytes), frames 20-48 differ."""
    import hashlib
    import os
    import tempfile

    from hapticfluid.bake import rebake_plan, scene_from_dict

    from hapticfluid_blender.bake import blender_scene
    from support import frames_on_disk, remove_on_exit, settings

    scene, probe = record_a_sweep_over_frames_1_to_48(source=True)
    bake = settings(scene)
    bake.resolution, bake.substeps = 16, 1
    bake.frame_start, bake.frame_end = 1, 48
    bake.cache_dir = remove_on_exit(tempfile.mkdtemp(prefix="hf_punch_rebake_"))
    t0 = time.monotonic()
    check(bpy.ops.hapticfluid.bake() == {"FINISHED"}, f"baked 1-48 ({time.monotonic() - t0:.1f} s)")

    def files():
        out = {}
        for name in frames_on_disk(bake.cache_dir):
            path = os.path.join(bake.cache_dir, "data", name)
            st = os.stat(path)
            with open(path, "rb") as f:
                out[name] = (st.st_ino, st.st_mtime_ns, hashlib.sha256(f.read()).hexdigest())
        return out

    baked = files()
    check(len(baked) == 48, f"48 frame files ({len(baked)})")
    time.sleep(0.05)  # a rewrite within the same clock tick could keep the mtime
    scene.hapticfluid_live.hand_gesture = "CIRCLE"
    run = start(scene, warm_s=1.5)
    play(run, range(1, 21))
    record()
    play(run, range(21, 31))
    record()
    live_ops.stop_all()
    check(run.controller.last_take == (20.0, 30.0, False), f"punched in over 20-30 ({run.controller.last_take})")

    plan = rebake_plan(scene_from_dict(blender_scene.scene_dict(scene, bake)))
    print(f"MEASURED rebake plan after the punch-in: {plan.kind}, first frame {plan.first_frame}, checkpoint "
          f"{plan.checkpoint_frame}: {plan.text}")
    check(plan.kind == "inputs" and plan.first_frame == 20 and plan.checkpoint_frame < 20,
          f"the plan re-bakes from frame 20 from a checkpoint before it: {plan.text}")
    t0 = time.monotonic()
    check(bpy.ops.hapticfluid.bake_resume() == {"FINISHED"}, f"one press re-bakes ({time.monotonic() - t0:.1f} s)")
    rebaked = files()
    names = sorted(baked)
    kept = [n for n in names[:19] if rebaked.get(n) == baked[n]]
    rewritten = [n for n in names[19:] if rebaked[n][:2] != baked[n][:2]]
    # Frame 20 is re-baked (its key at 20, the pose at A, was written again) but may come out the
    # same bytes: the take starts where the played motion was. Every frame after it differs.
    changed = [n for n in names[20:] if rebaked[n][2] != baked[n][2]]
    check(len(kept) == 19, f"frames 1-19 not rewritten: the same inode, mtime and bytes ({len(kept)} of 19)")
    check(len(rewritten) == 29, f"frames 20-48 re-baked (written again: {len(rewritten)} of 29)")
    check(len(changed) == 28, f"frames 21-48 different ({len(changed)} of 28; unchanged: "
                              f"{sorted(set(names[20:]) - set(changed))})")


def main():
    hapticfluid_blender.register()
    timeline_record_keys_what_plays()
    punch_in_with_the_simulated_falcon()
    punch_in_with_the_mouse()
    rebake_after_a_punch_in()
    hapticfluid_blender.unregister()
    print("record and punch-in: ok")


main()
