# SPDX-License-Identifier: GPL-3.0-or-later
"""``python3 -m hapticfluid haptic``: short headless runs write the trace CSV and its plot."""

import csv

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import cli, haptic_cli

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
SMALL = ["--resolution", "16", "16", "16", "--iterations", "20", "--probe-radius", "0.15"]


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def test_short_run_writes_csv_and_png(tmp_path, capsys):
    rc = cli.main(["haptic", "--seconds", "1.0", "--out", str(tmp_path), "--max-force", "2.5"] + SMALL)
    assert rc == 0
    out = capsys.readouterr().out
    assert "haptic_rate_hz" in out and "sim_rate_hz" in out
    # The gain in use and why (the scripted handle reports no rendering limits: gain 1), the
    # passivity controller's state and what the device did to the hand.
    assert "reports no rendering limits" in out and "passivity_delivered" in out and "mean_power_w" in out
    header, values = read_csv(tmp_path / haptic_cli.CSV_NAME)
    assert header == haptic_cli.CSV_COLUMNS
    assert len(values) > 100  # about 1000 periods at 1 kHz; generous for a loaded machine
    assert np.all(np.isfinite(values))
    assert values[0, 0] == 0.0 and np.all(np.diff(values[:, 0]) > 0)
    # The scripted sweep moves the handle along x within its amplitude.
    assert np.ptp(values[:, 1]) > 0.0 and np.abs(values[:, 1]).max() <= haptic_cli.SWEEP_AMPLITUDE_M[0] + 1e-6
    assert np.linalg.norm(values[:, 10:13], axis=1).max() <= 2.5 * (1 + 1e-5)  # CSV keeps 6 digits
    data = (tmp_path / haptic_cli.PNG_NAME).read_bytes()
    assert data.startswith(PNG_SIGNATURE) and len(data) > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == [haptic_cli.CSV_NAME, haptic_cli.PNG_NAME]


def test_host_device_run_is_driven_by_pushes(tmp_path):
    rc = cli.main(["haptic", "--device", "host", "--seconds", "0.8", "--no-plot", "--out", str(tmp_path)]
                  + SMALL)
    assert rc == 0
    _, values = read_csv(tmp_path / haptic_cli.CSV_NAME)
    assert np.ptp(values[:, 1]) > 0.0  # the pushed sweep reached the handle
    assert not (tmp_path / haptic_cli.PNG_NAME).exists()


def test_bad_arguments_exit_2(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["haptic", "--seconds", "-1"])
    assert exc.value.code == 2
    rc = cli.main(["haptic", "--device", "null", "--script", "x.csv", "--out", str(tmp_path)])
    assert rc == 2
    assert "--script" in capsys.readouterr().err


@pytest.mark.parametrize("args, message", [
    (["--gravity", "0", "0", "nan"], "argument --gravity: must be a finite number, got nan"),
    (["--force-gain", "x"], "argument --force-gain: expected a number, got 'x'"),
    (["--probe-radius", "0"], "argument --probe-radius: must be a positive finite number, got 0"),
    (["--resolution", "16", "16", "4"], "argument --resolution: need at least 8 cells per axis, got 4"),
])
def test_bad_numbers_are_named(args, message, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["haptic", *args])
    assert exc.value.code == 2
    assert message in capsys.readouterr().err


def test_pressure_solver_choice(tmp_path, capsys):
    rc = cli.main(["haptic", "--device", "null", "--seconds", "0.3", "--no-plot", "--solver", "multigrid",
                   "--resolution", "16", "16", "16", "--probe-radius", "0.15", "--out", str(tmp_path)])
    assert rc == 0
    with pytest.raises(SystemExit) as exc:
        cli.main(["haptic", "--solver", "sor"])
    assert exc.value.code == 2
    with pytest.raises(hf.InvalidArgumentError, match="solver must be"):
        haptic_cli.run_haptic(hf.null_device(), 0.1, tmp_path, solver="sor", log=lambda _l: None)


def test_simulated_falcon_run(tmp_path):
    rc = cli.main(["haptic", "--device", "simulated-falcon", "--seconds", "0.8", "--no-plot",
                   "--out", str(tmp_path)] + SMALL)
    assert rc == 0
    header, values = read_csv(tmp_path / haptic_cli.CSV_NAME)
    assert len(values) > 100 and np.all(np.isfinite(values))
    assert np.linalg.norm(values[:, 10:13], axis=1).max() <= 8.0 * (1 + 1e-5)  # the Falcon's maximum


def test_built_in_path_starts_at_rest_and_loops():
    h = 1e-4
    start = np.array(haptic_cli.sweep_position(0.0))
    velocity = (np.array(haptic_cli.sweep_position(h)) - start) / h
    assert np.abs(velocity).max() < 1e-3  # m/s: no impulsive start
    period = haptic_cli.SWEEP_PERIOD_S
    assert np.allclose(haptic_cli.sweep_position(period), start, atol=1e-12)
    times, positions = haptic_cli.sweep_waypoints()
    assert np.ptp(positions[:, 0]) == pytest.approx(2 * haptic_cli.SWEEP_AMPLITUDE_M[0], rel=1e-3)
