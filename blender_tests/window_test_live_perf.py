# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs in a windowed Blender under xvfb-run: the live demo's scene (1 m domain, source at its floor,
sphere probe on the simulated Falcon, its hand sweeping the probe through the plume) runs from the
3D view's Start operator at 32^3, 48^3 and 64^3, one session after another, and prints what an
artist gets on this machine: viewport redraws per second (the drawer's draw callbacks), simulation
Hz, haptic Hz and pose-to-force latency p50/p99 (the session's stats), the stale-force threshold in
use and how often the hand force was zero while measured (a slow simulation's force must not fade
between its frames), each beside the load average (the machine may be shared). The figures are
printed, not asserted (speed belongs to benchmarks); the test fails only if a session does not
start, publishes no frames or does not stop. Exits 0 when every check passed, 1 otherwise."""

import os
import threading
import time

import bpy

from support import check, clear_objects, cube, drive, fail, ico_sphere, invoke, set_roles, uv_sphere

import hapticfluid_blender  # noqa: E402  (support put the add-on on sys.path)
from hapticfluid_blender.live import live_ops  # noqa: E402

RESOLUTIONS = (32, 48, 64)
WARMUP_S = 4.0      # after the first snapshot: the rates settle
MEASURE_S = 8.0     # wall seconds counted per resolution
state = {"phase": "start", "index": 0, "t0": time.time(), "phase_t": time.time(), "rows": []}


def setup():
    hapticfluid_blender.register()
    scene = clear_objects()
    domain = cube(1.0, (0.5, 0.5, 0.5))
    domain.display_type = "WIRE"
    source = ico_sphere(0.08, (0.5, 0.5, 0.14))
    source.display_type = "WIRE"
    set_roles(scene, domain, uv_sphere(0.08, (0.28, 0.5, 0.55)), source)
    live = scene.hapticfluid_live
    live.device = "SIMULATED_FALCON"
    live.hand_gesture = "SWEEP"
    live.auto_resolution = False


def sample_hand_force(session):
    """Counts, every 10 ms on its own thread (no bpy: the session's latest() only), how often the
    force commanded to the hand is zero; the Blender timer runs too rarely under load to see it."""
    box = {"n": 0, "zero": 0, "stop": threading.Event()}

    def run():
        while not box["stop"].wait(0.01):
            box["n"] += 1
            box["zero"] += not any(session.latest()["commanded_force"])

    box["thread"] = threading.Thread(target=run, name="hand-force-sampler", daemon=True)
    box["thread"].start()
    return box


def next_phase(name):
    state["phase"] = name
    state["phase_t"] = time.time()


def step():
    scene = bpy.context.scene
    live = scene.hapticfluid_live
    phase = state["phase"]
    run = live_ops.run_for(scene)
    if phase == "start":
        res = RESOLUTIONS[state["index"]]
        live.resolution = res
        check(invoke(bpy.ops.hapticfluid.live_start) == {"RUNNING_MODAL"}, f"a session starts at {res}^3")
        next_phase("warmup")
    elif phase == "warmup":
        if run is None:
            fail(f"the session at {RESOLUTIONS[state['index']]}^3 ended: {live.status}")
        if run.controller.state == "running" and run.controller.last_sequence >= 1 \
                and time.time() - state["phase_t"] > WARMUP_S:
            state["frames0"] = run.drawer.frames_drawn if run.drawer is not None else 0
            state["seq0"] = run.controller.last_sequence
            state["load0"] = os.getloadavg()[0]
            state["hand"] = sample_hand_force(run.controller.session)
            next_phase("measure")
    elif phase == "measure":
        if run is None:
            fail(f"the session at {RESOLUTIONS[state['index']]}^3 ended while measured: {live.status}")
        elapsed = time.time() - state["phase_t"]
        if elapsed >= MEASURE_S:
            state["hand"]["stop"].set()
            state["hand"]["thread"].join()
            frames = (run.drawer.frames_drawn if run.drawer is not None else 0) - state["frames0"]
            snapshots = run.controller.last_sequence - state["seq0"]
            res = RESOLUTIONS[state["index"]]
            row = dict(res=res, redraw_hz=frames / elapsed, snap_hz=snapshots / elapsed, sim_hz=live.sim_rate_hz,
                       haptic_hz=live.haptic_rate_hz, p50=live.latency_p50_ms, p99=live.latency_p99_ms,
                       hand_n=live.device_force_n, fluid_n=live.force_n,
                       stale_s=run.controller.session.stats()["stale_after"],
                       hand_zero=state["hand"]["zero"] / max(1, state["hand"]["n"]),
                       load=(state["load0"] + os.getloadavg()[0]) / 2.0)
            state["rows"].append(row)
            print(f"measured {res}^3: viewport {row['redraw_hz']:.1f} redraws/s, simulation {row['sim_hz']:.1f} Hz "
                  f"(new frames drawn {row['snap_hz']:.1f}/s), haptic {row['haptic_hz']:.0f} Hz, latency p50 "
                  f"{row['p50']:.0f} ms p99 {row['p99']:.0f} ms; stale threshold {row['stale_s']:.2f} s, hand force "
                  f"zero in {row['hand_zero']:.0%} of {state['hand']['n']} samples; load average {row['load']:.1f} "
                  f"on {os.cpu_count()} CPUs", flush=True)
            check(snapshots > 0 and live.sim_rate_hz > 0.0 and live.haptic_rate_hz > 0.0,
                  f"{res}^3: frames published ({snapshots}) and stats arrive")
            check(bpy.ops.hapticfluid.live_stop() == {"FINISHED"}, f"{res}^3: Stop runs")
            next_phase("stopped")
    elif phase == "stopped":
        if run is None and not live.is_running:
            state["index"] += 1
            if state["index"] < len(RESOLUTIONS):
                next_phase("start")
            else:
                print("live session in Blender on this machine (simulated Falcon, llvmpipe, xvfb):", flush=True)
                print("  cells  redraws/s  sim Hz  haptic Hz  latency p50 / p99 ms  stale s  hand 0 N  load avg",
                      flush=True)
                for r in state["rows"]:
                    print(f"  {r['res']:>3}^3  {r['redraw_hz']:>9.1f}  {r['sim_hz']:>6.1f}  {r['haptic_hz']:>9.0f}  "
                          f"{r['p50']:>9.0f} / {r['p99']:<9.0f}  {r['stale_s']:>7.2f}  {r['hand_zero']:>8.0%}  "
                          f"{r['load']:>8.1f}", flush=True)
                print("blender live perf test passed", flush=True)
                os._exit(0)
        elif time.time() - state["phase_t"] > 20:
            fail("Stop did not end the session")
    return 0.1


setup()
drive(step, 500, lambda: f"in phase {state['phase']} (status: {bpy.context.scene.hapticfluid_live.status})")
