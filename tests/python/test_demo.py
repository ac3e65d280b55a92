# SPDX-License-Identifier: GPL-3.0-or-later
"""The demo scene (hapticfluid.demo) and the command line (python3 -m hapticfluid)."""

import csv
import math
import os
import stat
import subprocess
import sys

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import cli, demo

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
SMALL = dict(resolution=(16, 16, 16), domain_size=(1.0, 1.0, 1.0), steps=8, dt=0.05,
             iterations=4)  # multigrid, the default solver


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    lines = []
    result = demo.run_demo(out_dir=out, log=lines.append, **SMALL)
    return result, lines


def _read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def test_csv_has_a_finite_row_per_frame(small_run):
    result, _ = small_run
    assert result.csv_path.name == "force.csv" and result.csv_path.is_file()
    header, rows = _read_csv(result.csv_path)
    assert header == ["frame", "time_s", "probe_x_m", "probe_y_m", "probe_z_m", "probe_vx_m_s",
                      "force_x_n", "force_y_n", "force_z_n", "residual", "step_ms"]
    assert len(rows) == SMALL["steps"]
    values = np.array([[float(v) for v in row] for row in rows])
    assert np.all(np.isfinite(values))
    assert values[:, 0].tolist() == list(range(1, SMALL["steps"] + 1))
    np.testing.assert_allclose(values[:, 1], SMALL["dt"] * np.arange(1, SMALL["steps"] + 1),
                               rtol=1e-5)
    np.testing.assert_allclose(values[:, 6:9], result.forces, rtol=1e-5, atol=1e-9)
    # The measured residual is a fraction, not the -1 of "not measured".
    assert np.all(values[:, 9] >= 0.0)
    # No temporary files are left behind by the atomic writes.
    assert sorted(p.name for p in result.out_dir.iterdir()) == ["density.png", "force.csv"]


def test_png_is_written(small_run):
    result, _ = small_run
    assert result.png_path is not None and result.png_path.name == "density.png"
    data = result.png_path.read_bytes()
    assert data.startswith(PNG_SIGNATURE)
    assert len(data) > 10_000  # a real figure, not an empty canvas


def test_probe_stays_inside_with_a_margin(small_run):
    result, _ = small_run
    h = 1.0 / SMALL["resolution"][0]
    radius = max(demo.DemoScene().probe_radius * 1.0, 1.5 * h)
    x = result.probe_positions[:, 0]
    assert np.all(x - radius >= h - 1e-9) and np.all(x + radius <= 1.0 - h + 1e-9)
    assert np.ptp(x) > 0.05  # it does sweep
    assert np.max(np.abs(result.probe_velocities[:, 0])) <= demo.DemoScene().max_speed + 1e-9


def test_force_is_nonzero_while_the_probe_moves(small_run):
    result, _ = small_run
    moving = np.abs(result.probe_velocities[:, 0]) > 1e-3
    assert moving.any()
    assert np.all(np.isfinite(result.forces))
    # Pushing air aside takes a horizontal force, whatever the resolution.
    assert np.max(np.abs(result.forces[moving, 0])) > 1e-5


def test_buoyancy_while_parked(small_run):
    result, _ = small_run
    parked = np.abs(result.probe_velocities[:, 0]) == 0.0
    assert parked.any()
    # At rest the vertical force is about the displaced air's weight (voxelised volume: loose).
    fz = result.forces[parked, 2]
    radius = max(demo.DemoScene().probe_radius, 1.5 / SMALL["resolution"][0])
    buoyancy = 1.2 * 9.81 * 4.0 / 3.0 * math.pi * radius ** 3
    assert np.all(fz > 0.5 * buoyancy) and np.all(fz < 2.0 * buoyancy)


def test_result_and_log(small_run):
    result, lines = small_run
    assert result.forces.shape == (SMALL["steps"], 3)
    assert result.steps_per_s > 0.0 and math.isfinite(result.steps_per_s)
    assert result.paths == [result.csv_path, result.png_path]
    text = "\n".join(lines)
    assert result.device["renderer"] in text
    assert "steps/s" in text and "excluded" in text
    assert str(result.csv_path) in text and str(result.png_path) in text


def test_sweep_velocity_is_the_derivative_of_the_position():
    sweep = demo._Sweep((0.5, 0.5, 0.5), amplitude=0.3, t0=1.0, period=2.0)
    assert sweep.pose(0.5) == ((0.2, 0.5, 0.5), (0.0, 0.0, 0.0))
    eps = 1e-6
    for t in (1.1, 1.5, 2.0, 2.7):
        (x0, _, _), _ = sweep.pose(t - eps)
        (x1, _, _), _ = sweep.pose(t + eps)
        _, (vx, vy, vz) = sweep.pose(t)
        assert vx == pytest.approx((x1 - x0) / (2 * eps), rel=1e-5, abs=1e-6)
        assert vy == 0.0 and vz == 0.0


def test_run_demo_rejects_bad_arguments(tmp_path):
    with pytest.raises(hf.InvalidArgumentError, match="steps"):
        demo.run_demo(out_dir=tmp_path, steps=0, log=None)
    with pytest.raises(hf.InvalidArgumentError, match="dt"):
        demo.run_demo(out_dir=tmp_path, dt=-1.0, log=None)
    with pytest.raises(hf.InvalidArgumentError, match="cubic"):
        demo.run_demo(out_dir=tmp_path, resolution=(16, 16, 32), steps=1, log=None)


def _cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-W", "error", "-m", "hapticfluid", *args],
                          capture_output=True, text=True, env=dict(os.environ), cwd=cwd,
                          timeout=120)


@pytest.mark.parametrize(
    "args, message",
    [
        (["demo", "--steps", "0"], "argument --steps: must be a positive integer, got 0"),
        (["demo", "--resolution", "4", "4", "4"], "argument --resolution: need at least 8 cells"),
        (["demo", "--dt", "nan"], "argument --dt"),
        (["demo", "--advection", "upwind"], "argument --advection: invalid choice"),
        # Python 3.11's argparse says "expected 3 arguments"; 3.13's takes --out as the third
        # value and says "expected a cell count, got '--out'"
        (["demo", "--resolution", "16", "16"], "argument --resolution: expected "),
        ([], "the following arguments are required: COMMAND"),
    ],
)
def test_cli_rejects_bad_arguments(args, message, tmp_path):
    proc = _cli(*args, "--out", str(tmp_path / "out")) if args else _cli()
    assert proc.returncode == 2
    assert message in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not (tmp_path / "out").exists()


def test_cli_reports_engine_argument_errors_without_traceback(tmp_path):
    # Not cubic cells: argparse accepts it, the engine refuses it (InvalidArgumentError).
    proc = _cli("demo", "--resolution", "16", "16", "32", "--steps", "1", "--out", str(tmp_path))
    assert proc.returncode == 2
    assert "error: cells must be cubic" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_cli_help():
    proc = _cli("demo", "--help")
    assert proc.returncode == 0
    for option in ("--resolution", "--domain", "--steps", "--dt", "--iterations", "--solver", "--device",
                   "--out", "--advection"):
        assert option in proc.stdout


def test_cli_demo_runs(tmp_path):
    out = tmp_path / "cli"
    proc = _cli("demo", "--resolution", "16", "16", "16", "--steps", "3", "--solver", "jacobi",
                "--iterations", "10", "--out", str(out))
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""
    assert "steps/s" in proc.stdout and "10 Jacobi sweeps" in proc.stdout
    header, rows = _read_csv(out / "force.csv")
    assert len(rows) == 3
    assert (out / "density.png").read_bytes().startswith(PNG_SIGNATURE)


def test_cli_info(capsys):
    assert cli.main(["info"]) == 0
    text = capsys.readouterr().out
    assert "renderer" in text and "EGL devices:" in text


def test_outputs_have_the_usual_file_mode(tmp_path):
    result = demo.run_demo(resolution=(16, 16, 16), steps=2, out_dir=tmp_path, plot=False, log=lambda line: None)
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(result.csv_path.stat().st_mode) == 0o666 & ~mask


def test_demo_solver_choice(tmp_path):
    with pytest.raises(hf.InvalidArgumentError, match="solver must be one of 'jacobi', 'multigrid'"):
        demo.run_demo(out_dir=tmp_path, solver="sor", log=None, **SMALL)
    lines = []
    demo.run_demo(out_dir=tmp_path, solver="multigrid", log=lines.append, plot=False,
                  **{**SMALL, "iterations": None, "steps": 2})
    assert any(f"{demo.DEFAULT_ITERATIONS['multigrid']} multigrid-CG iterations" in line for line in lines), lines
