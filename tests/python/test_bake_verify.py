# SPDX-License-Identifier: GPL-3.0-or-later
"""Resume checks the frames: a deleted or truncated frame file is found and rebaked (it used to
stay missing while resume said "finished"), and `bake --verify` reports it without baking."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hapticfluid.bake import bake, frame_path, list_frames, read_manifest, scene_from_dict
from hapticfluid.bake import cache as bake_cache
from hapticfluid.bake import verify as bake_verify
from hapticfluid.bake.openvdb_python import import_openvdb, missing_reason

vdb = import_openvdb()
if vdb is None:
    pytest.skip(missing_reason(), allow_module_level=True)

FRAMES = 4


def scene_dict(cache):
    return {
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 16,
        "fluid": {"heat_buoyancy": 1.5, "vorticity": 0.3, "open_top": True, "pressure_iterations": 15},
        "source": {"centre": [0.5, 0.5, 0.2], "radius": 0.15, "temperature": 6.0},
        "probe": {"shape": "sphere", "radius": 0.12,
                  "keys": [{"frame": 0, "location": [0.3, 0.5, 0.55]},
                           {"frame": FRAMES, "location": [0.7, 0.5, 0.55]}]},
        "frames": {"start": 1, "end": FRAMES, "fps": 24},
        "substeps": 2,
        "cache": {"directory": str(cache), "grids": ["density", "velocity", "pressure"], "tolerance": 0.0},
    }


def grids(cache, frame):
    out = {}
    for name in ("density", "velocity", "pressure"):
        grid = vdb.read(str(frame_path(cache, frame)), name)
        a = np.zeros((16, 16, 16) + ((3,) if name == "velocity" else ()), dtype=np.float32)
        grid.copyToArray(a, ijk=(0, 0, 0))
        out[name] = a
    return out


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """A finished bake of FRAMES frames, copied by each test that damages it."""
    cache = tmp_path_factory.mktemp("ref") / "c"
    result = bake(scene_from_dict(scene_dict(cache)))
    assert result.status == "finished" and list_frames(cache) == list(range(1, FRAMES + 1))
    return cache


@pytest.fixture
def baked(reference, tmp_path):
    cache = tmp_path / "c"
    shutil.copytree(reference, cache)
    return cache


def run_cli(cache, *extra):
    scene = cache.parent / "scene.json"
    scene.write_text(json.dumps(scene_dict(cache)))
    return subprocess.run([sys.executable, "-m", "hapticfluid", "bake", str(scene), "--quiet", *extra],
                          capture_output=True, text=True, timeout=300, env=dict(os.environ))


def assert_same_frames(a, b, frames):
    for frame in frames:
        ga, gb = grids(a, frame), grids(b, frame)
        for name in ga:
            np.testing.assert_array_equal(ga[name], gb[name], err_msg=f"frame {frame} {name}")


def test_the_manifest_records_each_frames_size_and_digest(reference):
    records = read_manifest(reference)["frame_records"]
    assert sorted(records, key=int) == [str(f) for f in range(1, FRAMES + 1)]
    for f in range(1, FRAMES + 1):
        written = {k: v for k, v in records[str(f)].items() if k != "inputs"}  # inputs: plan.py's
        assert written == bake_verify.frame_record(frame_path(reference, f))
        assert records[str(f)]["bytes"] == frame_path(reference, f).stat().st_size


def test_verify_of_a_sound_cache_says_so(baked):
    proc = run_cli(baked, "--verify")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert f"all {FRAMES} frame file(s) the manifest lists are sound" in proc.stdout


def test_a_deleted_middle_frame_is_reported_and_rebaked_on_resume(baked, reference):
    frame_path(baked, 2).unlink()
    proc = run_cli(baked, "--verify")
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "frame 2: missing" in proc.stdout and "1 of 4 frame file(s)" in proc.stdout
    assert not frame_path(baked, 2).exists()  # --verify bakes nothing

    lines = []
    result = bake(scene_from_dict(scene_dict(baked)), resume=True, log=lines.append)
    assert result.status == "finished" and result.damaged_frames == (2,)
    assert result.frames_written == FRAMES - 1  # 2, 3 and 4: the replay keeps frame 1 as it was
    assert any("frame 2: missing" in line for line in lines)
    assert list_frames(baked) == list(range(1, FRAMES + 1))
    assert_same_frames(reference, baked, range(1, FRAMES + 1))
    manifest = read_manifest(baked)
    assert manifest["complete"] and manifest["frames_done"] == list(range(1, FRAMES + 1))
    assert manifest["sessions"][-1]["rebaked_damaged_frames"] == [2]
    assert run_cli(baked, "--verify").returncode == 0


def test_a_truncated_last_frame_is_reported_and_rebaked_on_resume(baked, reference):
    last = frame_path(baked, FRAMES)
    data = last.read_bytes()
    last.write_bytes(data[: len(data) // 2])
    proc = run_cli(baked, "--verify")
    assert proc.returncode == 1
    assert f"frame {FRAMES}: truncated or changed: {len(data) // 2} bytes, the bake wrote {len(data)}" in proc.stdout

    proc = run_cli(baked, "--resume")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert f"rebaked missing or damaged frame(s) {FRAMES}" in proc.stdout
    assert "bake finished: 1 frame(s)" in proc.stdout
    assert_same_frames(reference, baked, range(1, FRAMES + 1))
    assert run_cli(baked, "--verify").returncode == 0


def test_a_changed_frame_of_the_same_size_is_found_by_its_digest(baked):
    path = frame_path(baked, 3)
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    report = bake_verify.verify_cache(baked)
    assert list(report.damaged) == [3] and "SHA-256" in report.damaged[3]


def test_resume_works_without_a_readable_manifest(baked, reference):
    bake_cache.manifest_path(baked).write_text("[1, 2, 3]")  # a JSON list, not the manifest
    frame_path(baked, 3).unlink()
    lines = []
    result = bake(scene_from_dict(scene_dict(baked)), resume=True, log=lines.append)
    assert any("is not a JSON object" in line for line in lines)
    assert result.status == "finished" and result.damaged_frames == (3,)
    assert_same_frames(reference, baked, range(1, FRAMES + 1))
    assert read_manifest(baked)["complete"]
    # Without records, frames are checked by their header: a file that is no VDB is damaged.
    frame_path(baked, 1).write_bytes(b"not a vdb file")
    bake_cache.write_manifest(baked, {k: v for k, v in read_manifest(baked).items() if k != "frame_records"})
    assert bake_verify.verify_cache(baked).damaged == {1: "not an OpenVDB file (no VDB header)"}


@pytest.mark.parametrize("text, what", [("[1, 2]", "not a JSON object"), ("[" * 100000, "RecursionError"),
                                        ("1" * 5000, "ValueError"), (b"\xff\xfe{", "UnicodeDecodeError")],
                         ids=["list", "deep", "5000-digit-int", "not-utf8"])
def test_a_damaged_manifest_is_a_bake_error_that_points_to_resume(tmp_path, text, what):
    path = bake_cache.manifest_path(tmp_path)
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    with pytest.raises(bake_cache.BakeError, match=f"{what}.*--resume"):
        read_manifest(tmp_path)
