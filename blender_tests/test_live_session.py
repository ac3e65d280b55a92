# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside `blender --background --factory-startup --python-exit-code 1`: the live session.

Modal operators get no events in --background, so this drives the controller and the operator
helpers (live_ops.start / tick / stop_all) directly: register and unregister twice; a session on
the simulated Falcon moves the probe object to the device pose (and its scripted hand, Hand
Gesture Sweep, sweeps it across the domain); in Mouse mode moving the object moves the probe (the
fluid force opposes the motion, so it changes sign with the direction) and turning it turns the
fluid's probe (the bake's pose: the same cells); Record keys the performed poses, location and
rotation in the object's rotation mode (replacing keys in that range); every bad setup gives a report
that starts with the fix; disabling the add-on, read_homefile and open_mainfile during a session
stop it. Measures (prints, never asserts) simulation Hz, haptic Hz and latency at 32^3 and 48^3.
Any failure raises, so Blender exits 1."""

import math
import os
import sys
import tempfile
import threading
import time

import bpy

from support import check, cube, empty_file, set_roles, settings

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
import hapticfluid as hf  # noqa: E402
from hapticfluid_blender.live import live_ops, live_session, recording  # noqa: E402

RAMP_S = hf.HapticSessionSettings().ramp_time  # the force's ramp-in after the first step (s)


def new_scene(probe_at=(0.5, 0.5, 0.5), fluid_density=1.2):
    """Empty file: a 1 m domain cube with its corner at the origin, a 0.2 m cube probe."""
    scene = empty_file()
    domain = cube(1.0, (0.5, 0.5, 0.5), "Domain")
    probe = cube(0.2, probe_at, "Probe")
    bake = set_roles(scene, domain, probe)
    bake.fluid_density = fluid_density
    bake.pressure_iterations = 20
    live = scene.hapticfluid_live
    live.auto_resolution = False
    live.resolution = 16
    bpy.context.view_layer.update()
    return scene, domain, probe


def live_threads():
    return [t for t in threading.enumerate() if t.name.startswith("hapticfluid-live")]


def run_for_seconds(run, seconds, each=None):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if each is not None:
            each()
        state = live_ops.tick(run)
        if state == "stopped":
            raise AssertionError(f"the session stopped: {run.controller.report}")
        time.sleep(live_ops.TICK_S)


def register_twice():
    for _ in range(2):
        hapticfluid_blender.register()
        check(hasattr(bpy.types.Scene, "hapticfluid_live") and hasattr(bpy.ops.hapticfluid, "live_start"),
              "register adds the live settings and operators")
        hapticfluid_blender.unregister()
        check(not hasattr(bpy.types.Scene, "hapticfluid_live"), "unregister removes them")
    hapticfluid_blender.register()
    from hapticfluid_blender.live import live_panel

    check(live_panel.package_problem() is None, "the preferences find the package importable")


def simulated_falcon_moves_the_probe():
    scene, _domain, probe = new_scene(probe_at=(0.35, 0.6, 0.45))
    scene.hapticfluid_live.device = "SIMULATED_FALCON"
    run = live_ops.start(scene)
    run.controller.wait_started()
    check(scene.hapticfluid_live.is_running, "the session runs")
    c = run.controller
    # Paced by the session, not the wall: from its first simulation step, the force's ramp-in and
    # 0.5 s more (the hand settles on its spring).
    deadline = time.monotonic() + 60.0
    while c.session.stats()["sim_steps"] == 0:
        check(time.monotonic() < deadline, "the simulation steps")
        run_for_seconds(run, 0.05)
    run_for_seconds(run, RAMP_S + 1.0)
    # The hand's force over the next second, at every tick: its median (a loaded machine's late
    # step lets the safety stage fade a stale force for a moment).
    forces = []
    run_for_seconds(run, 1.0, each=lambda: forces.append(float(c.session.latest_force[2])))
    # The simulated hand rests at the middle of the workspace, which the fitted map puts at the
    # domain's centre: the probe object is moved there from where it started. The hand (300 N/m)
    # yields to the force it feels, the probe's buoyancy at the derived gain (about 1.4 N up here,
    # 5 mm of the device, 60 mm of the domain): it is allowed for along z, once that force is shown
    # to be the buoyancy x the gain (within 20%: the cube's voxels give 0.89 of its volume), so a
    # wrong force cannot widen its own tolerance.
    loc = probe.matrix_world.translation
    stats = c.session.stats()
    hand_z_n = sorted(forces)[len(forces) // 2]
    buoyancy_n = 1.2 * 9.81 * 0.2 ** 3  # air, the 0.2 m cube probe
    expected_n = float(stats["force_gain"]) * buoyancy_n
    yield_m = 12.5 * abs(hand_z_n) / 300.0  # domain m: workspace scale x the hand's give
    print("probe at", tuple(loc), "device state", scene.hapticfluid_live.device_state, "hand force z (median of",
          len(forces), "ticks)", hand_z_n, "gain x buoyancy", expected_n)
    check(abs(hand_z_n - expected_n) <= 0.2 * expected_n,
          f"the hand feels the probe's buoyancy x the gain: {hand_z_n:.3f} N up ({expected_n:.3f} N: gain "
          f"{stats['force_gain']:.4g} x {buoyancy_n:.4f} N)")
    check(all(abs(loc[i] - 0.5) < 0.02 for i in range(2)) and abs(loc[2] - 0.5) < 0.02 + 1.5 * yield_m,
          f"the probe follows the device to the centre: {tuple(loc)} (hand force z {hand_z_n:.3f} N)")
    check(c.last_sequence >= 2, f"field snapshots arrive ({c.last_sequence})")
    live = scene.hapticfluid_live
    check(live.sim_rate_hz > 0.0 and live.haptic_rate_hz > 0.0,  # their pace: tests/cpp (HapticLoop), pytest
          f"stats are live: sim {live.sim_rate_hz:.1f} Hz, haptic {live.haptic_rate_hz:.0f} Hz")
    check("homed" in live.device_state and "not homed" not in live.device_state, live.device_state)
    session = c.session
    report = live_ops.stop_all()[0]
    check(report is None, f"Stop ends it without a report ({report})")
    check(session.state == "stopped" and not live_threads() and not live.is_running,
          "threads joined, session stopped")
    check(tuple(session.latest_force) == (0.0, 0.0, 0.0), "the force went to zero")


def the_feel_choice_reaches_the_session():
    """Feel: Amplified (the derived gain, the default) or Physical 1:1, sent as the session's feel;
    the stats line puts what the hand feels against what the fluid gives."""
    from hapticfluid_blender.live import live_panel

    scene, _domain, _probe = new_scene()
    live = scene.hapticfluid_live
    check(live.feel == "AMPLIFIED", f"Amplified by default ({live.feel})")
    check(live_session.read_plan(scene).session_args["feel"] == "amplified", "the plan asks for it")
    live.feel = "PHYSICAL"
    live.device = "SIMULATED_FALCON"
    check(live_session.read_plan(scene).session_args["feel"] == "physical", "Physical 1:1 reaches the plan")
    run = live_ops.start(scene)
    run.controller.wait_started()
    st = run.controller.session.stats()
    check(st["feel"] == "physical" and st["force_gain"] == 1.0, f"the session renders 1:1 ({st['feel']}, {st['force_gain']})")
    live_ops.stop_all()
    text = live_panel.feel_text(1.1534, 0.046234, 24.87)
    check(text == "1.15 N on the hand = 0.0462 N in the fluid x 24.9", text)


def simulated_hand_sweeps_the_probe():
    """Hand Gesture 'Sweep': the simulated hand moves the grip back and forth along x after
    homing, and the probe object follows it across the domain."""
    scene, _domain, probe = new_scene(probe_at=(0.5, 0.5, 0.5))
    live = scene.hapticfluid_live
    live.device = "SIMULATED_FALCON"
    live.hand_gesture = "SWEEP"
    run = live_ops.start(scene)
    run.controller.wait_started()
    xs = []
    run_for_seconds(run, 4.5, each=lambda: xs.append(probe.matrix_world.translation.x))
    # +-0.025 m of the Falcon's workspace mapped onto the 1 m domain (uniform fit): about +-0.3 m.
    check(max(xs) > 0.7 and min(xs) < 0.3, f"the probe sweeps across the domain: x {min(xs):.3f} .. {max(xs):.3f} m")
    # Record while Blender ticks twice a second (a slow viewport): the keys come from the hand's
    # poses of every haptic period (the session's trace), not from the ticks alone.
    c = run.controller
    c.start_recording()
    ticks = 0
    t0 = time.monotonic()
    while time.monotonic() - t0 < 2.0:
        time.sleep(0.5)
        live_ops.tick(run)
        ticks += 1
    samples = len(c.recording.samples)
    seconds = time.monotonic() - t0
    n = c.stop_recording()
    live_ops.stop_all()
    check(samples >= 5 * ticks, f"Record took the hand's poses between ticks ({samples} poses over {ticks} ticks)")
    check(n >= 0.8 * scene.hapticfluid_live.record_rate * seconds,
          f"keys at the record rate: {n} in {seconds:.1f} s at {scene.hapticfluid_live.record_rate}/s")
    keyed = [p.co.y for p in recording.object_fcurves(probe).find("location", index=0).keyframe_points]
    check(min(keyed) > 0.1 and max(keyed) < 0.9, f"the keys stay on the sweep: x {min(keyed):.3f} .. {max(keyed):.3f} m")


class RecordingDrawer:
    """Stands in for live_draw.LiveDrawer (which does nothing in --background): keeps the calls."""

    def __init__(self):
        self.calls = {}

    def __getattr__(self, name):
        if not name.startswith("set_"):
            raise AttributeError(name)
        return lambda *args: self.calls.setdefault(name, []).append(args)


def the_drawer_gets_what_it_draws():
    scene, _domain, probe = new_scene()
    scene.hapticfluid_live.device = "SIMULATED_FALCON"
    drawer = RecordingDrawer()
    controller = live_session.LiveController(scene, drawer=drawer)
    controller.wait_started()
    end = time.monotonic() + 1.0
    while time.monotonic() < end or "set_density" not in drawer.calls:
        controller.tick()
        time.sleep(0.02)
    c = drawer.calls
    check(c["set_domain"] == [((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))], f"the domain box: {c['set_domain']}")
    (lo, hi), = c["set_workspace_box"]
    check(all(-1e-5 <= lo[i] and hi[i] <= 1.0 + 1e-5 for i in range(3))
          and any(abs(hi[i] - lo[i] - 1.0) < 1e-4 for i in range(3)),
          f"the fitted Falcon workspace fills the domain on its tightest axis: {lo} {hi}")
    density, temperature = c["set_density"][-1]
    check(density.shape == (16, 16, 16) and str(density.dtype) == "float32" and temperature is None,
          f"density [x, y, z] float32 at the session's resolution {density.shape}")
    origin, force, max_force = c["set_force"][-1]
    check(all(abs(origin[i] - probe.matrix_world.translation[i]) < 1e-6 for i in range(3)) and len(force) == 3
          and max_force == scene.hapticfluid_live.max_force, "the force arrow at the probe, scaled by Max Force")
    # The arrow is the force the hand feels (device N after the gain) in world axes, the same
    # newtons as Max Force: its length is the commanded force's, its axes the world's. (A tick a
    # stats period after the last writes the figures from the latest it draws.)
    time.sleep(live_session.STATS_PERIOD_S)
    controller.tick()
    _o, drawn, _m = c["set_force"][-1]
    latest = controller.session.latest()
    check(math.isclose(math.hypot(*drawn), scene.hapticfluid_live.device_force_n, rel_tol=1e-5, abs_tol=1e-9),
          f"the arrow's newtons are the device force shown in Stats ({math.hypot(*drawn):.4g} N = "
          f"{scene.hapticfluid_live.device_force_n:.4g} N), not the fluid force ({scene.hapticfluid_live.force_n:.4g} N "
          f"at gain {scene.hapticfluid_live.force_gain_used:.3g})")
    world = controller.hand_force_world(latest)
    check(len(world) == 3 and world == tuple(float(c) for c in latest["commanded_force_world"])
          and math.isclose(math.hypot(*world), math.hypot(*latest["commanded_force"]), rel_tol=1e-6, abs_tol=1e-12),
          "hand_force_world is the engine's commanded force in world axes (commanded_force_world), the same newtons")
    check(c["set_display"] == [(scene.hapticfluid_live.density_scale, False)], "the display settings")
    scene.hapticfluid_live.density_scale = 5.0
    controller.tick()
    check(c["set_display"][-1] == (5.0, False), "a display change during the session reaches the drawer")
    controller.stop()


def the_panel_figures_are_written_once_a_period():
    """The panel's figures are written at the first tick and then at most every STATS_PERIOD_S:
    each write of an add-on's property redraws every region of the window (it redrew the whole
    window at every tick, 40 times a second, and cost the viewport 2-3 % of its pace)."""
    scene, _domain, _probe = new_scene()
    scene.hapticfluid_live.device = "SIMULATED_FALCON"
    clock = [100.0]
    controller = live_session.LiveController(scene, clock=lambda: clock[0])
    controller.wait_started()
    live = scene.hapticfluid_live
    controller.tick()
    check(live.device_state.startswith(controller.engine.device.info().name), f"the first tick writes them: {live.device_state!r}")
    live.device_state = "not written since"
    clock[0] += 0.5 * live_session.STATS_PERIOD_S
    controller.tick()
    check(live.device_state == "not written since", f"not again within the period: {live.device_state!r}")
    clock[0] += 0.5 * live_session.STATS_PERIOD_S
    controller.tick()
    check(live.device_state.startswith(controller.engine.device.info().name),
          f"again once the period is over: {live.device_state!r}")
    controller.stop()


def mouse_moves_the_probe_and_record_keys_it():
    scene, _domain, probe = new_scene(probe_at=(0.5, 0.5, 0.5), fluid_density=1000.0)
    scene.hapticfluid_live.device = "MOUSE"
    run = live_ops.start(scene)
    run.controller.wait_started()
    # Each direction: 0.3 m at constant speed; the mean force of the simulation steps that began
    # at least two steps after the first moved pose was pushed (a step already running used an
    # older pose) and 0.3 s into the motion (past the start's transient), one sample per step.
    speed, travel_s = 0.12, 2.5  # m/s, s
    forces = {}
    session = run.controller.session
    for direction in (1.0, -1.0):
        t0, x0 = time.monotonic(), probe.location.x
        first_moving_step = None
        per_step = {}
        while time.monotonic() - t0 < travel_s:  # the whole travel: several cell crossings
            t = time.monotonic() - t0
            probe.location.x = x0 + direction * speed * min(t, travel_s)
            bpy.context.view_layer.update()
            live_ops.tick(run)  # pushes the moved pose
            steps = session.stats()["sim_steps"]
            if first_moving_step is None and t > 0.0:
                first_moving_step = steps
            if steps >= first_moving_step + 2 and 0.3 <= t < travel_s:
                per_step[steps] = session.latest()["sim_force"][0]
            time.sleep(live_ops.TICK_S)
        check(len(per_step) >= 3, f"enough steps during the motion ({len(per_step)})")
        forces[direction] = sum(per_step.values()) / len(per_step)
        print(f"moving {'+' if direction > 0 else '-'}x at {speed} m/s: mean fluid force x {forces[direction]:.3f} N "
              f"over {len(per_step)} steps")
        run_for_seconds(run, 0.3)
    check(forces[1.0] < 0.0 < forces[-1.0], f"the fluid force opposes the motion and changes sign: {forces}")
    live_ops.stop_all()

    # Record with a controlled clock: one key per 1/24 s at 24 fps, replacing keys in the range.
    scene, _domain, probe = new_scene(probe_at=(0.5, 0.5, 0.5))
    scene.hapticfluid_live.device = "MOUSE"
    scene.render.fps, scene.render.fps_base = 24, 1.0
    scene.hapticfluid_live.record_rate = 24.0
    scene.frame_set(10)
    probe.location = (0.5, 0.5, 0.5)
    probe.keyframe_insert("location", frame=12)   # inside the recorded range: replaced
    probe.location = (0.45, 0.5, 0.5)
    probe.keyframe_insert("location", frame=40)   # outside it: kept
    probe.rotation_euler = (0.0, 0.0, 0.0)
    clock = [100.0]
    controller = live_session.LiveController(scene, clock=lambda: clock[0])
    controller.wait_started()
    performed = []
    for k in range(6):
        clock[0] = 100.0 + k / 24.0
        probe.location = (0.4 + 0.02 * k, 0.5, 0.5 + 0.01 * k)
        probe.rotation_euler = (0.0, 0.0, 0.1 * k)
        bpy.context.view_layer.update()
        if k == 0:
            controller.start_recording()  # keys the pose at the start at once
        else:
            controller.tick()
        performed.append((10.0 + k, tuple(probe.location), tuple(probe.rotation_euler)))
        clock[0] += 0.01  # a second tick within the same key interval adds no key
        controller.tick()
    n = controller.stop_recording()
    check(n == 6, f"one key per 1/24 s ({n})")
    fcurves = recording.object_fcurves(probe)
    compared = 0
    for path, slot in (("location", 1), ("rotation_euler", 2)):
        for index in range(3):
            keys = {round(p.co.x, 4): p.co.y for p in fcurves.find(path, index=index).keyframe_points}
            for frame, loc, rot in performed:
                value = (loc, rot)[slot - 1][index]
                if abs(keys.get(round(frame, 4), math.nan) - value) > 1e-6:
                    raise AssertionError(f"{path}[{index}] key at frame {frame}: {keys.get(round(frame, 4))} != {value}")
                compared += 1
    check(compared == 36, "every recorded key holds the performed location and rotation")
    loc_x = {round(p.co.x, 4): p.co.y for p in fcurves.find("location", index=0).keyframe_points}
    check(set(loc_x) == {10.0, 11.0, 12.0, 13.0, 14.0, 15.0, 40.0},
          f"keys of the recorded range replaced, the one outside kept: {sorted(loc_x)}")
    check(abs(loc_x[40.0] - 0.45) < 1e-6, "the key outside the range keeps its value")
    controller.stop()
    check(controller.session.state == "stopped", "stopped")


def record_keys_the_path_at_the_record_rate():
    """Record's keys come at the record rate however rarely Blender ticked while recording: each
    one on the path performed between the two samples around it (a quaternion on the shorter arc)."""
    samples = [(10.0, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)),
               (13.0, (0.3, 0.0, 0.0), (-math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5))),  # 90 deg about z, negated
               (13.5, (0.3, 0.1, 0.0), (-math.sqrt(0.5), 0.0, 0.0, -math.sqrt(0.5)))]
    keys = recording.resample(samples, 1.0, quaternion=True)
    check([k[0] for k in keys] == [10.0, 11.0, 12.0, 13.0], f"a key per frame up to the last sample: {keys}")
    check(all(abs(k[1][0] - 0.1 * (k[0] - 10.0)) < 1e-9 and k[1][1] == 0.0 for k in keys),
          "locations on the straight path between the samples around each key")
    w, _, _, z = keys[1][2]
    check(abs(w * w + z * z - 1.0) < 1e-9 and w > 0.0 and z > 0.0 and abs(math.atan2(z, w) * 2.0 - math.pi / 6) < 0.02,
          f"a unit quaternion turned a third of the way on the shorter arc: {keys[1][2]}")
    check(recording.resample([], 2.0) == [] and len(recording.resample(samples[:1], 2.0)) == 1,
          "no samples: no keys; one sample: one key")


def mouse_turns_a_mesh_probe_and_record_keys_the_rotation():
    """A box probe turned with R (here: its rotation set, as R does) turns in the fluid: the
    simulation's probe transform is the object's matrix_world, the matrix the bake gives
    set_probe_pose, and it covers the cells a bake-like pose covers. Record keys the turn in the
    object's rotation mode (quaternion here)."""
    import numpy as np
    from mathutils import Quaternion

    scene, _domain, probe = new_scene(probe_at=(0.5, 0.5, 0.5), fluid_density=1000.0)
    probe.scale = (1.3, 1.0, 0.7)  # kept from Start (the status says when it changes)
    probe.rotation_mode = "QUATERNION"
    probe.rotation_quaternion = (1.0, 0.0, 0.0, 0.0)
    scene.render.fps, scene.render.fps_base = 24, 1.0
    scene.hapticfluid_live.record_rate = 24.0
    scene.frame_set(1)
    bpy.context.view_layer.update()
    scene.hapticfluid_live.device = "MOUSE"
    run = live_ops.start(scene)
    run.controller.wait_started()
    c = run.controller
    sim = c.engine.sim
    c.start_recording()
    performed = []
    for k in range(1, 9):  # a quarter turn about a tilted axis over about a second
        q = Quaternion((0.3, -0.2, 1.0), 0.2 * k)
        probe.rotation_quaternion = q
        bpy.context.view_layer.update()
        performed.append(tuple(q))
        run_for_seconds(run, 0.13)
    steps = c.session.stats()["sim_steps"]
    end = time.monotonic() + 30.0
    while c.session.stats()["sim_steps"] < steps + 2 and time.monotonic() < end:
        run_for_seconds(run, 0.1)  # a step that began after the last turn
    world = np.array(probe.matrix_world)
    got = np.array(sim.probe["transform"])
    check(np.allclose(got, world, atol=2e-5), f"the fluid's probe turns with the object: {got.round(4)} vs {world.round(4)}")
    live_cells = sim.cell_classes()  # of the session's latest step, which used the turned pose
    n = c.stop_recording()
    check(n >= 8, f"Record keyed the turn ({n} keys)")
    fcurves = recording.object_fcurves(probe)
    keyed = [tuple(fcurves.find("rotation_quaternion", index=i).evaluate(fr) for i in range(4))
             for fr in sorted({p.co.x for p in fcurves.find("rotation_quaternion", index=0).keyframe_points})]
    check(fcurves.find("rotation_euler", index=0) is None, "keyed in the object's rotation mode (quaternion only)")
    for q in performed:
        check(any(max(abs(a - b) for a, b in zip(q, kq)) < 1e-5 for kq in keyed),
              f"a key holds the performed rotation {tuple(round(v, 4) for v in q)}")
    live_ops.stop_all()

    # The pose the bake gives: the object's matrix_world (as performed: the keys now drive the
    # object, at the current frame the first one) to set_mesh_probe / set_probe_pose.
    import hapticfluid as hf
    from hapticfluid_blender.bake import blender_scene

    shape = blender_scene.probe_shape_dict(probe, "MESH")
    plan = c.plan
    res = c.engine.resolution
    h = (plan.domain_hi[0] - plan.domain_lo[0]) / res[0]
    with hf.Simulation(resolution=res, domain_size=tuple(n * h for n in res), origin=plan.domain_lo,
                       **plan.fluid) as bake:
        bake.set_mesh_probe(np.asarray(shape["vertices"], np.float32), np.asarray(shape["triangles"], np.int32),
                            world.tolist())
        bake.step(0.01)
        unturned = (live_cells != bake.cell_classes()).sum()
        check(unturned == 0, f"the live probe covers the cells the bake's pose covers ({unturned} differ)")
        bake.set_probe_pose([list(r) for r in c.start_matrix])
        bake.step(0.01)
        check((live_cells != bake.cell_classes()).any(), "... which the unturned probe does not")


def timeline_drives_a_sphere_probe():
    scene, _domain, probe = new_scene(probe_at=(0.3, 0.5, 0.5))
    settings(scene).probe_shape = "SPHERE"
    probe.keyframe_insert("location", frame=1)
    probe.location.x = 0.7
    probe.keyframe_insert("location", frame=20)
    scene.frame_set(1)
    scene.hapticfluid_live.device = "TIMELINE"
    run = live_ops.start(scene)
    run.controller.wait_started()
    sim = run.controller.engine.sim
    check(sim.probe["kind"] == "sphere" and abs(sim.probe["radius"] - 0.1) < 1e-6, "a sphere probe of the object's size")
    for frame in range(1, 21):
        scene.frame_set(frame)
        run_for_seconds(run, 0.05)
    run_for_seconds(run, 0.5)  # the simulation thread takes the newest pose at its next step
    x = float(sim.probe["centre"][0])
    check(abs(x - 0.7) < 1e-3, f"the timeline moved the probe in the simulation to x = 0.7 m ({x:.4f})")
    live_ops.stop_all()


def deleted_objects_and_device_errors_end_it():
    for what in ("probe", "domain", "device"):
        scene, domain, probe = new_scene()
        scene.hapticfluid_live.device = "SIMULATED_FALCON"
        run = live_ops.start(scene)
        run.controller.wait_started()
        run_for_seconds(run, 0.2)
        session = run.controller.session
        if what == "probe":
            bpy.data.objects.remove(probe)
        elif what == "domain":
            bpy.data.objects.remove(domain)
        else:
            run.controller.engine.device.close()  # what unplugging looks like to the session
            time.sleep(0.2)
        check(live_ops.tick(run) == "stopped" and session.state in ("stopped", "failed") and not live_ops._RUNNING
              and not live_threads(), f"a {what} {'error' if what == 'device' else 'deleted'} ends the session")
        words = {"probe": "'Probe' was deleted", "domain": "'Domain' was deleted", "device": "read() after close()"}[what]
        check(words in (run.controller.report or ""), f"the report names the cause: {run.controller.report}")
        if what == "device":
            check(run.controller.report.startswith("Check the device's cable"), "... after the fix")


def bad_setups():
    def report_for(prepare, mode="MOUSE"):
        scene, domain, probe = new_scene()
        scene.hapticfluid_live.device = mode
        prepare(scene, domain, probe)
        bpy.context.view_layer.update()
        try:
            run = live_ops.start(scene)
            run.controller.wait_started()
        except live_session.SessionError as exc:
            live_ops.stop_all()
            check(not live_threads(), "no thread left behind")
            return str(exc)
        live_ops.stop_all()
        raise AssertionError("the bad setup was accepted")

    def expect(prepare, *words, mode="MOUSE", first=None):
        text = report_for(prepare, mode)
        check(all(w in text for w in words), f"report names the problem ({words}): {text[:160]}")
        if first is not None:
            check(text.startswith(first), f"the report starts with the fix '{first}'")

    def no_domain(s, d, p):
        settings(s).domain = None
    expect(no_domain, "Domain role", first="Give a mesh the Domain role")

    def rotated(s, d, p):
        d.rotation_euler = (0.0, 0.0, 0.3)
    expect(rotated, "turned", "Alt+R", first="Clear the rotation")

    def rotation_applied(s, d, p):  # Ctrl+A on a turned box: the mesh itself is no longer axis-aligned
        from mathutils import Matrix

        d.data.transform(Matrix.Rotation(0.3, 4, "Z"))
    expect(rotation_applied, "axis-aligned box", first="Make the domain")

    def no_probe(s, d, p):
        settings(s).probe = None
    expect(no_probe, "Probe role", first="Give an object the Probe role")

    def not_a_mesh(s, d, p):
        bpy.ops.object.empty_add(location=(0.5, 0.5, 0.5))
        settings(s).probe = bpy.context.active_object
    expect(not_a_mesh, "not a mesh", "Sphere shape", first="Choose a mesh object")

    def open_mesh(s, d, p):
        bpy.ops.mesh.primitive_monkey_add(size=0.3, location=(0.5, 0.5, 0.5))
        settings(s).probe = bpy.context.active_object
    expect(open_mesh, "Fill Holes", "Recalculate Outside", first="Close the probe")

    def outside(s, d, p):
        p.location = (1.5, 0.5, 0.5)
    expect(outside, "inside the domain", first="Move the probe")

    def no_falcon(s, d, p):
        pass
    expect(no_falcon, "Falcon", mode="FALCON")

    def firmware_missing(s, d, p):
        s.hapticfluid_live.firmware_path = "/nonexistent/nvent_firmware.bin"
    expect(firmware_missing, "firmware", "/nonexistent/nvent_firmware.bin", mode="FALCON",
           first="Choose the Falcon firmware")

    saved = sys.modules.get("hapticfluid")
    sys.modules["hapticfluid"] = None  # what an uninstalled package looks like to `import`
    try:
        expect(lambda s, d, p: None, "not importable", first="Install the hapticfluid package")
        from hapticfluid_blender.live import live_panel

        problem = live_panel.package_problem()  # what the preferences and the sidebar show
        check(problem is not None and problem.startswith("Install the hapticfluid package"),
              f"the add-on's preferences say the package is missing: {problem}")
    finally:
        sys.modules["hapticfluid"] = saved

    os.environ["HAPTICFLUID_EGL_DEVICE"] = "no-such-egl-device"
    try:
        expect(lambda s, d, p: None, "GL context", first="Check the GPU driver")
    finally:
        del os.environ["HAPTICFLUID_EGL_DEVICE"]


def sessions_end_with_the_addon_and_the_file():
    for how in ("unregister", "read_homefile", "open_mainfile"):
        scene, _domain, _probe = new_scene()
        scene.hapticfluid_live.device = "SIMULATED_FALCON"
        run = live_ops.start(scene)
        run.controller.wait_started()
        run_for_seconds(run, 0.3)
        session = run.controller.session
        if how == "unregister":
            hapticfluid_blender.unregister()
        elif how == "read_homefile":
            bpy.ops.wm.read_homefile(use_empty=True)
        else:
            with tempfile.TemporaryDirectory() as tmp:
                path = os.path.join(tmp, "other.blend")
                bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
                bpy.ops.wm.open_mainfile(filepath=path)
        check(session.state == "stopped" and run.controller.state == "stopped" and not live_ops._RUNNING
              and not live_threads(), f"{how} during a session stops it (threads joined)")
        check(run.controller.report is not None, f"... with a report: {run.controller.report}")
        if how == "unregister":
            hapticfluid_blender.register()
        else:
            live = bpy.context.scene.hapticfluid_live
            check(not live.is_running, "the new file has no running session")


def measure():
    for res in (32, 48, 64):
        scene, _domain, probe = new_scene(fluid_density=1.2)
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.05, location=(0.5, 0.5, 0.15))
        settings(scene).source = bpy.context.active_object
        settings(scene).pressure_iterations = 40
        scene.hapticfluid_live.resolution = res
        scene.hapticfluid_live.device = "MOUSE"
        run = live_ops.start(scene)
        run.controller.wait_started()
        t0 = time.monotonic()

        def move():
            probe.location.x = 0.5 + 0.2 * math.sin(2.0 * (time.monotonic() - t0))
            bpy.context.view_layer.update()

        end = time.monotonic() + 90.0  # at least 12 steps (or 90 s) so the rates are measured, not guessed
        while run.controller.session.stats()["sim_steps"] < 12 and time.monotonic() < end:
            run_for_seconds(run, 0.5, each=move)
        s = run.controller.session.stats()
        print(f"MEASURED live session {res}^3 in Blender (mouse mode, multigrid CG to 1e-3): sim {s['sim_rate_hz']:.1f} Hz, "
              f"step {s['sim_step_ms']:.1f} ms, haptic {s['haptic_rate_hz']:.0f} Hz, jitter p99 "
              f"{s['jitter_p99_ms']:.3f} ms, latency p50 {s['latency_p50_ms']:.1f} ms p99 {s['latency_p99_ms']:.1f} ms, "
              f"snapshots {s['snapshots']}, steps {s['sim_steps']}, realtime {s['realtime']}, load average "
              f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores", flush=True)
        live_ops.stop_all()


def main():
    register_twice()
    simulated_falcon_moves_the_probe()
    the_feel_choice_reaches_the_session()
    simulated_hand_sweeps_the_probe()
    the_drawer_gets_what_it_draws()
    the_panel_figures_are_written_once_a_period()
    mouse_moves_the_probe_and_record_keys_it()
    record_keys_the_path_at_the_record_rate()
    mouse_turns_a_mesh_probe_and_record_keys_the_rotation()
    timeline_drives_a_sphere_probe()
    deleted_objects_and_device_errors_end_it()
    bad_setups()
    sessions_end_with_the_addon_and_the_file()
    measure()
    hapticfluid_blender.unregister()
    print("live session: ok")


main()
