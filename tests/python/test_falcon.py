# SPDX-License-Identifier: GPL-3.0-or-later
"""The Falcon driver from Python: enumeration, the simulated Falcon through the whole driver,
argument errors, and the `devices` command."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import hapticfluid
import hapticfluid as hf
import hapticfluid.hand_gestures
from hapticfluid import devices_cli


def test_list_falcons_describes_each_one():
    falcons = hf.list_falcons()
    assert isinstance(falcons, list)
    for f in falcons:  # none on a machine without a Falcon
        assert set(f) == {"index", "bus", "address", "serial", "permission_ok", "firmware_loaded", "problem"}
        assert f["bus"] > 0 and f["address"] > 0


def test_open_falcon_without_one_says_so():
    if hf.list_falcons(probe_firmware=False):
        pytest.skip("a Falcon is plugged in")
    with pytest.raises(hf.HapticFluidError, match="no Novint Falcon"):
        hf.open_falcon()


def test_open_falcon_firmware_file_must_exist(tmp_path):
    with pytest.raises(hf.InvalidArgumentError, match="cannot be found"):
        hf.open_falcon(firmware=str(tmp_path / "nvent_firmware.bin"))
    empty = tmp_path / "empty.bin"
    empty.write_bytes(b"")
    with pytest.raises(hf.InvalidArgumentError, match="is empty"):
        hf.open_falcon(firmware=str(empty))


def test_simulated_falcon_is_homed_and_pushes_back():
    with hf.open_simulated_falcon() as dev:
        assert isinstance(dev, hf.FalconDevice)
        info = dev.info()
        assert info.kind == "simulated_falcon"
        assert info.max_force == pytest.approx(8.0)
        assert dev.read().homed
        # The simulated hand holds the grip with 300 N/m: 1.5 N along -x moves it 5 mm.
        for _ in range(1500):
            state = dev.read()
            dev.write_force((-1.5, 0.0, 0.0))
        assert state.position[0] == pytest.approx(-1.5 / 300.0, abs=5e-4)
        assert abs(state.position[1]) < 5e-4 and abs(state.position[2]) < 5e-4
        stats = dev.stats()
        assert stats["packets"] >= 1500
        assert stats["upload_attempts"] == 0 and not stats["firmware_uploaded"]


def test_simulated_falcon_uploads_the_firmware_it_is_given():
    image = bytes((i * 97 + 5) % 256 for i in range(7324))  # synthetic, not Novint's
    dev = hf.open_simulated_falcon(firmware_bytes=image)
    stats = dev.stats()
    assert stats["firmware_uploaded"] and stats["upload_attempts"] == 1
    assert dev.read().homed
    dev.close()
    dev.close()  # idempotent
    with pytest.raises(hf.HapticFluidError, match="after close"):
        dev.read()


def test_homing_on_demand():
    dev = hf.open_simulated_falcon(home=False)
    state = dev.read()
    assert not state.homed
    with pytest.raises(hf.InvalidArgumentError, match="homing timeout"):
        dev.home(timeout=0.0)
    dev.home(timeout=10.0)
    assert dev.read().homed
    dev.close()


@pytest.mark.parametrize("kwargs, match", [
    ({"hand_mass": 0.0}, "hand mass"),
    ({"hand_stiffness": math.nan}, "hand stiffness"),
    ({"max_force": 20.0}, "peak force"),
    ({"homing_timeout": -1.0}, "homing timeout"),
    ({"firmware_bytes": b""}, "firmware_bytes is empty"),
])
def test_simulated_falcon_argument_errors(kwargs, match):
    with pytest.raises(hf.InvalidArgumentError, match=match):
        hf.open_simulated_falcon(**kwargs)


def test_unplug_mid_session_raises_and_stops_cleanly():
    dev = hf.open_simulated_falcon(unplug_after=500)
    with pytest.raises(hf.HapticFluidError, match="was unplugged"):
        for _ in range(1000):
            dev.read()
            dev.write_force((0.0, 2.0, 0.0))
    with pytest.raises(hf.HapticFluidError, match="unplugged"):
        dev.read()
    dev.write_force((0.0, 2.0, 0.0))  # nothing to send it to: ignored
    dev.close()
    dev.close()
    with pytest.raises(hf.InvalidArgumentError, match="unplug_after"):
        hf.open_simulated_falcon(unplug_after=0)


def test_non_finite_force_is_rejected():
    with hf.open_simulated_falcon() as dev:
        with pytest.raises(hf.InvalidArgumentError, match="finite"):
            dev.write_force((math.inf, 0.0, 0.0))


def test_devices_report_explains_permission_problems():
    lines = devices_cli.format_falcons([
        {"index": 0, "bus": 3, "address": 9, "serial": "", "permission_ok": False,
         "firmware_loaded": None, "problem": "libusb_open: LIBUSB_ERROR_ACCESS"},
        {"index": 1, "bus": 3, "address": 12, "serial": "FTB3ABCD", "permission_ok": True,
         "firmware_loaded": False, "problem": ""},
    ])
    text = "\n".join(lines)
    assert "[0] bus 003 address 009" in text
    assert "no permission" in text and 'ATTRS{idProduct}=="cb48"' in text and "udevadm" in text
    assert "serial FTB3ABCD" in text and "firmware: not loaded" in text
    assert "none plugged in" in "\n".join(devices_cli.format_falcons([]))


def test_devices_command_runs(tmp_path):
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(hf.__file__)))
    out = subprocess.run([sys.executable, "-m", "hapticfluid", "devices"], capture_output=True, text=True,
                         env=env, cwd=tmp_path, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "Novint Falcons (USB 0403:cb48):" in out.stdout
    assert "simulated_falcon" in out.stdout and "open_simulated_falcon()" in out.stdout
    if not hf.list_falcons(probe_firmware=False):
        assert "none plugged in" in out.stdout


def grip_positions(dev, seconds):
    """The grip's positions over `seconds` of simulated time (one packet per ms)."""
    return np.array([dev.read().position for _ in range(int(seconds * 1000))])


def test_simulated_hand_follows_a_scripted_path():
    # After homing (0.6 s) the hand pulls the grip to 2 cm along x over 0.5 s and holds it there.
    with hf.open_simulated_falcon(hand_path=[(0.5, 0.02, 0.0, 0.0)]) as dev:
        p = grip_positions(dev, 2.0)
        np.testing.assert_allclose(p[-1], (0.02, 0.0, 0.0), atol=5e-4)


def test_relaxed_hand_homes_then_rests_lightly_on_the_grip():
    # 300 N/m while homing (the grip reaches the pull-out), 5 N/m once homed: a 0.5 N push moves it
    # 10 cm's worth against the hand, so it goes as far as the workspace lets it within 0.5 s.
    with hf.open_simulated_falcon(**hapticfluid.hand_gestures.falcon_args("relaxed")) as dev:
        assert dev.read().homed
        for _ in range(500):
            dev.write_force((0.5, 0.0, 0.0))
            x = dev.read().position[0]
        assert x > 0.02, x
    with hf.open_simulated_falcon() as dev:  # the default hand: 300 N/m throughout
        for _ in range(500):
            dev.write_force((0.5, 0.0, 0.0))
            x = dev.read().position[0]
        assert x < 0.002, x


def test_simulated_hand_loops_a_gesture():
    args = hapticfluid.hand_gestures.falcon_args("sweep")
    assert args["hand_loop"] and len(args["hand_path"]) == 3
    with hf.open_simulated_falcon(**args) as dev:
        x = grip_positions(dev, 8.0)[:, 0]
        late = x[5000:]  # two sweeps after the first one: still sweeping (looped, not held)
        assert late.max() > 0.02 and late.min() < -0.02, (late.min(), late.max())
    assert hapticfluid.hand_gestures.falcon_args("rest") == {"hand_path": None, "hand_loop": False}
    relaxed = hapticfluid.hand_gestures.falcon_args("relaxed")
    assert relaxed["hand_path"] is None and relaxed["hand_stiffness_homed"] == 5.0
    with pytest.raises(ValueError, match="gesture must be one of rest, sweep, circle"):
        hapticfluid.hand_gestures.waypoints("wave")


@pytest.mark.parametrize("path, loop, match", [
    ([], False, "at least one waypoint"),
    ([(0.0, 0.0, 0.0, 0.0)], True, "two waypoints to loop"),
    ([(0.0, 0.2, 0.0, 0.0)], False, "waypoint 0 .* out of the Falcon's reach"),
    ([(0.0, math.nan, 0.0, 0.0)], False, "waypoint 0"),
    ([(1.0, 0.0, 0.0, 0.0), (0.5, 0.01, 0.0, 0.0)], False, "waypoint 1: its time"),
    ([(-1.0, 0.0, 0.0, 0.0)], False, "waypoint 0: its time"),
])
def test_simulated_hand_path_errors_name_it(path, loop, match):
    with pytest.raises(hf.InvalidArgumentError, match=match):
        hf.open_simulated_falcon(hand_path=path, hand_loop=loop)
    with pytest.raises(hf.InvalidArgumentError, match="hand_path"):
        hf.open_simulated_falcon(hand_path=path, hand_loop=loop)
