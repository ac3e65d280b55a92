# SPDX-License-Identifier: GPL-3.0-or-later
"""Ctrl-C on the bake CLI (issue 19): the first SIGINT stops after the substep, a second one stops
at once; either way the process exits 130 with a message, never by the signal (-2) and never with
a traceback, wherever the signals land: in a native step, while a frame (.vdb) or the checkpoint
is written, or while the process is already winding down after the first one."""

import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hapticfluid.bake.cache import list_frames


def scene(cache, frames=400, resolution=24):
    return {
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": resolution,
        "fluid": {"heat_buoyancy": 1.5, "pressure_iterations": 10},
        "source": {"centre": [0.5, 0.5, 0.2], "radius": 0.15, "temperature": 6.0},
        "probe": {"shape": "sphere", "radius": 0.12,
                  "keys": [{"frame": 0, "location": [0.3, 0.5, 0.55]},
                           {"frame": frames, "location": [0.7, 0.5, 0.55]}]},
        "frames": {"start": 1, "end": frames, "fps": 24},
        "substeps": 1,
        "cache": {"directory": str(cache), "grids": ["density", "velocity", "pressure"], "tolerance": 0.0},
    }


def start_bake(tmp_path, name):
    scene_file = tmp_path / f"{name}.json"
    scene_file.write_text(json.dumps(scene(tmp_path / name)))
    out = open(tmp_path / f"{name}.out", "w+")
    err = open(tmp_path / f"{name}.err", "w+")
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "hapticfluid", "bake", str(scene_file), "--quiet"],
                            stdout=out, stderr=err, env=env)
    deadline = time.monotonic() + 120
    try:
        while len(list_frames(tmp_path / name)) < 1:  # baking: frames, checkpoints and steps interleave
            assert proc.poll() is None and time.monotonic() < deadline, "the bake did not start"
            time.sleep(0.002)
    except BaseException:  # no bake left running behind a failed test
        proc.kill()
        proc.wait()
        out.close()
        err.close()
        raise
    return proc, out, err


def finish(proc, out, err):
    proc.wait(timeout=120)
    with out, err:
        out.seek(0)
        err.seek(0)
        return proc.returncode, out.read(), err.read()


def check(rc, stdout, stderr, what):
    assert rc == 130, f"{what}: exit {rc} (-2: killed by SIGINT)\nstdout: {stdout}\nstderr: {stderr}"
    assert "Traceback" not in stderr, f"{what}: {stderr}"


def sigint_pairs():
    rng = random.Random(19)
    # (delay after the first frame s, gap between the two SIGINTs s): while it steps and writes.
    return [(rng.uniform(0.0, 0.4), gap) for gap in (0.0, 0.0005, 0.002, 0.01, 0.05, 0.2)]


@pytest.mark.parametrize("delay,gap", sigint_pairs())
def test_two_sigints_exit_130(tmp_path, delay, gap):
    proc, out, err = start_bake(tmp_path, "pair")
    time.sleep(delay)
    proc.send_signal(signal.SIGINT)
    if gap:
        time.sleep(gap)
    proc.send_signal(signal.SIGINT)
    rc, stdout, stderr = finish(proc, out, err)
    check(rc, stdout, stderr, f"two SIGINTs {gap * 1e3:g} ms apart")


def test_a_sigint_while_the_process_winds_down_after_the_first(tmp_path):
    """The first SIGINT ends the bake; the second arrives once the summary is printed, while the
    process exits (closing the GL context, interpreter teardown)."""
    for attempt in range(3):
        proc, out, err = start_bake(tmp_path, f"exit{attempt}")
        proc.send_signal(signal.SIGINT)
        deadline = time.monotonic() + 60
        while "bake cancelled" not in Path(out.name).read_text():
            assert time.monotonic() < deadline and proc.poll() is None, "no summary line"
            time.sleep(0.0005)
        time.sleep(0.001 * attempt)
        proc.send_signal(signal.SIGINT)
        rc, stdout, stderr = finish(proc, out, err)
        check(rc, stdout, stderr, f"SIGINT during exit (attempt {attempt})")


def test_a_storm_of_sigints(tmp_path):
    proc, out, err = start_bake(tmp_path, "storm")
    for _ in range(20):
        if proc.poll() is not None:
            break
        proc.send_signal(signal.SIGINT)
        time.sleep(0.001)
    rc, stdout, stderr = finish(proc, out, err)
    check(rc, stdout, stderr, "20 SIGINTs 1 ms apart")
