# SPDX-License-Identifier: GPL-3.0-or-later
"""Haptic playback from Python (HapticSession.set_guide / release_guide) on the simulated Falcon:
the fluid's probe takes the played pose, the device leads a relaxed hand to it, a release hands
the probe back to the grip. Timing is never asserted tightly (a loaded 2-core machine)."""

import math
import time

import pytest

import hapticfluid as hf
from hapticfluid import hand_gestures


def wait_until(predicate, timeout=20.0, interval=0.02, each=None):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if each is not None:
            each()
        if predicate():
            return True
        time.sleep(interval)
    return predicate()


def test_the_played_pose_leads_the_probe_and_the_grip_and_lets_go():
    played = (0.62, 0.45, 0.5)  # world m, 0.12 m and 0.05 m off the grip's start at the centre
    with hf.Simulation(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0), pressure_iterations=5) as sim:
        dev = hf.open_simulated_falcon(max_force=4.0, **hand_gestures.falcon_args("relaxed"))
        with hf.HapticSession(sim, dev, probe_radius=0.08, fit_workspace=True, max_force=4.0, ramp_time=0.1) as s:
            st = s.stats()
            assert (st["guide_stiffness"], st["guide_damping"], st["guide_max_force"]) == (750.0, 5.0, 2.0)
            assert st["guide_weight"] == 0.0

            def centre():
                return [float(v) for v in sim.probe["centre"]]

            def grip():
                return [float(v) for v in s.probe_origin(s.latest()["position"])]

            renew = lambda: s.set_guide(played, (0.0, 0.0, 0.0))  # noqa: E731 (the host's tick)
            assert wait_until(lambda: math.dist(centre(), played) < 1e-3, each=renew), centre()
            # The relaxed hand is led there: the fluid's push felt meanwhile is at most 0.2 N (0.1 of
            # the guide's 2 N), 0.27 mm at 750 N/m, 3.3 mm in the world at the fitted scale 12.5.
            # Led there means held there: within 6 mm at 10 polls in a row (0.2 s), not only once
            # on the way in (a grip still swinging in once read 7.2 mm off just after).
            near = []

            def held_near():
                near.append(math.dist(grip(), played) < 0.006)
                return len(near) >= 10 and all(near[-10:])

            assert wait_until(held_near, each=renew), grip()
            assert s.stats()["guide_weight"] == 1.0
            # latest() gives one haptic period's played pose, grip and guide force (device frame). The
            # resting grip steps between encoder counts; in a period whose grip velocity reads zero the
            # force is the spring alone on the offset that period saw, K e to float precision.
            one = s.latest()
            assert math.dist([float(v) for v in s.probe_origin(one["guide_target"])], played) < 1e-4
            assert math.dist([float(v) for v in s.probe_origin(one["grip"])], played) < 0.006
            spring_only = []
            for _ in range(40):
                renew()
                one = s.latest()
                spring = [750.0 * (float(one["guide_target"][i]) - float(one["grip"][i])) for i in range(3)]
                spring_only.append(math.dist(spring, [float(v) for v in one["guide_force"]]) < 1e-3)
                time.sleep(0.005)
            assert any(spring_only), spring_only
            s.release_guide()
            assert wait_until(lambda: s.stats()["guide_weight"] == 0.0, timeout=5.0)
            assert wait_until(lambda: math.dist(centre(), grip()) < 0.02), (centre(), grip())
        dev.close()


@pytest.mark.parametrize("name, value", [("guide_stiffness", 2300.0), ("guide_damping", 11.0)])
def test_guide_gains_beyond_the_falcons_limits_are_refused(name, value):
    with hf.Simulation(resolution=(16, 16, 16), pressure_iterations=5) as sim:
        dev = hf.open_simulated_falcon()
        with pytest.raises(hf.InvalidArgumentError, match=name):
            hf.HapticSession(sim, dev, **{name: value})
        dev.close()
