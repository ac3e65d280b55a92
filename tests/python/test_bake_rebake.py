# SPDX-License-Identifier: GPL-3.0-or-later
"""Re-bake from any frame: checkpoints kept every K frames, a manifest that records what each
frame consumed, and a resume that re-bakes only from the first frame whose inputs changed,
starting at the latest kept checkpoint before it. Each case is compared bit for bit with a
straight bake of the same scene."""

import hashlib
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from hapticfluid.bake import bake, free_cache, frame_path, list_frames, rebake_plan, scene_from_dict
from hapticfluid.bake import cache as bake_cache
from hapticfluid.bake.plan import describe_checkpoints, frame_states, verify_checkpoints
from hapticfluid.bake.openvdb_python import import_openvdb, missing_reason
from hapticfluid.bake.trajectory import Trajectory

vdb = import_openvdb()
if vdb is None:
    pytest.skip(missing_reason(), allow_module_level=True)

END = 30


def path_x(f, new_from=None):
    """The probe's x (m) at frame f: a slow sweep; from new_from on, another gesture."""
    x = 0.3 + 0.012 * f
    if new_from is not None and f >= new_from:
        x += 0.004 * (f - new_from + 1)
    return x


def scene(cache, end=END, new_from=None, every=10, **fluid):
    """Keys at every frame from 0 (as the add-on samples them), like a recorded performance."""
    return scene_from_dict(scene_json(cache, end, new_from, every, **fluid))


def scene_json(cache, end=END, new_from=None, every=10, **fluid):
    return ({
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 12,
        "fluid": {"heat_buoyancy": 1.5, "vorticity": 0.3, "pressure_iterations": 8, **fluid},
        "source": {"centre": [0.5, 0.5, 0.25], "radius": 0.15, "temperature": 6.0},
        "probe": {"shape": "sphere", "radius": 0.12,
                  "keys": [{"frame": f, "location": [path_x(f, new_from), 0.5, 0.55]} for f in range(0, end + 1)]},
        "frames": {"start": 1, "end": end, "fps": 24},
        "substeps": 1,
        "cache": {"directory": str(cache), "grids": ["density", "velocity", "pressure"], "tolerance": 0.0,
                  "checkpoint_every": every},
    })


def grid_digests(cache, frames):
    """SHA-256 of every grid's voxels per frame (density, velocity, pressure), and of the file:
    the writer derives the header's UUID from the content, so equal frames are equal files."""
    out = {}
    for f in frames:
        h = hashlib.sha256()
        for name, shape in (("density", (12, 12, 12)), ("velocity", (12, 12, 12, 3)), ("pressure", (12, 12, 12))):
            grid = vdb.read(str(frame_path(cache, f)), name)
            values = np.zeros(shape, dtype=np.float32)
            grid.copyToArray(values, ijk=(0, 0, 0))
            h.update(name.encode())
            h.update(values.tobytes())
        out[f] = (h.hexdigest(), hashlib.sha256(frame_path(cache, f).read_bytes()).hexdigest())
    return out


def file_ids(cache, frames):
    """(inode, mtime in ns) per frame file: unchanged when a re-bake keeps the file."""
    out = {}
    for f in frames:
        st = os.stat(frame_path(cache, f))
        out[f] = (st.st_ino, st.st_mtime_ns)
    return out


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    """Frames 1-30 baked in one go: the reference every re-bake must reproduce to the bit."""
    cache = tmp_path_factory.mktemp("straight")
    result = bake(scene(cache))
    assert result.status == "finished" and result.frames_written == END
    return cache


def test_checkpoints_are_kept_every_k_frames_and_listed(straight):
    assert bake_cache.list_kept_checkpoints(straight) == [10, 20, 30]
    manifest = bake_cache.read_manifest(straight)
    assert [c["frame"] for c in manifest["checkpoints"]] == [10, 20, 30]
    expected = scene(straight).checkpoint_bytes
    for c in manifest["checkpoints"]:  # the estimate the panel shows is the size on disk, within 2 KB
        assert abs(c["bytes"] - expected) < 2048, (c, expected)
    assert manifest["checkpoint_every"] == 10
    assert all("inputs" in manifest["frame_records"][str(f)] for f in range(1, END + 1))
    assert verify_checkpoints(scene(straight)) == {}
    assert rebake_plan(scene(straight)).kind == "complete"


def test_resume_from_a_kept_checkpoint_reproduces_the_straight_bake(straight, tmp_path):
    """Bake 1-30; delete frames 11-30; resume starts at the checkpoint at 10 and every frame
    is byte-identical to the straight bake, frames 1-10 not even rewritten."""
    cache = tmp_path / "c"
    bake(scene(cache))
    for f in range(11, END + 1):
        frame_path(cache, f).unlink()
    kept_ids = file_ids(cache, range(1, 11))
    plan = rebake_plan(scene(cache))
    assert (plan.kind, plan.first_frame, plan.checkpoint_frame) == ("damaged", 11, 10)
    assert plan.text == "frame 11 is missing: re-bake 11-30 from the checkpoint at 10"
    result = bake(scene(cache), resume=True)
    assert result.resumed_from == 10 and result.frames_written == 20
    assert file_ids(cache, range(1, 11)) == kept_ids
    assert grid_digests(cache, range(1, END + 1)) == grid_digests(straight, range(1, END + 1))
    assert bake_cache.list_kept_checkpoints(cache) == [10, 20, 30]


def test_changed_keys_rebake_from_the_checkpoint_before_the_change(tmp_path):
    """The probe's path changes from frame 18 on: frames 1-17 are kept untouched, 18-30 re-baked
    from the checkpoint at 10, and the cache then equals a straight bake of the changed scene."""
    cache, reference = tmp_path / "c", tmp_path / "ref"
    bake(scene(cache))
    bake(scene(reference, new_from=18))
    kept = file_ids(cache, range(1, 18))
    changed = scene(cache, new_from=18)
    plan = rebake_plan(changed)
    assert (plan.kind, plan.first_frame, plan.checkpoint_frame, plan.changed) == ("inputs", 18, 10, ("probe",))
    assert plan.text == "probe keys changed from frame 18: re-bake 18-30 from the checkpoint at 10"
    assert list(plan.valid_frames) == list(range(1, 18))
    assert frame_states(changed, plan) == [(1, 17, "baked"), (18, 30, "outdated")]
    result = bake(changed, resume=True)
    assert result.resumed_from == 10 and result.frames_written == 13 and result.plan.kind == "inputs"
    assert file_ids(cache, range(1, 18)) == kept
    assert grid_digests(cache, range(1, END + 1)) == grid_digests(reference, range(1, END + 1))
    assert rebake_plan(changed).kind == "complete"


def test_a_changed_global_setting_rebakes_every_frame(straight, tmp_path):
    cache = tmp_path / "c"
    bake(scene(cache, end=12))
    plan = rebake_plan(scene(cache, end=12, vorticity=0.9))
    assert (plan.kind, plan.first_frame, plan.changed) == ("settings", 1, ("fluid.vorticity",))
    assert plan.text == "fluid.vorticity changed: re-bake every frame, 1-12"
    plan = rebake_plan(scene(cache, end=12).with_resolution(16))
    assert plan.kind == "settings" and set(plan.changed) == {"grid_resolution", "resolution"}
    result = bake(scene(cache, end=12, vorticity=0.9), resume=True)
    assert result.frames_written == 12 and result.resumed_from is None
    # the global change is recorded: resuming again finds nothing to do
    assert rebake_plan(scene(cache, end=12, vorticity=0.9)).kind == "complete"


def test_until_stops_after_a_frame_and_the_next_resume_continues_bit_exact(straight, tmp_path):
    """Farm chunks: 1-12, then 13-24, then the rest; the cache equals the straight bake."""
    cache = tmp_path / "c"
    first = bake(scene(cache), resume=True, until=12)  # an empty cache: resume starts from the first frame
    assert first.status == "finished" and list_frames(cache) == list(range(1, 13))
    assert bake_cache.list_kept_checkpoints(cache) == [10, 12]  # the chunk's end is kept for the next
    assert rebake_plan(scene(cache)).text == "frames 1-12 baked: bake 13-30 from the checkpoint at 12"
    second = bake(scene(cache), resume=True, until=24)
    assert second.resumed_from == 12 and second.frames_written == 12
    third = bake(scene(cache), resume=True)
    assert third.resumed_from == 24 and third.frames_written == 6
    assert grid_digests(cache, range(1, END + 1)) == grid_digests(straight, range(1, END + 1))
    nothing = bake(scene(cache), resume=True, until=5)
    assert nothing.frames_written == 0
    with pytest.raises(Exception, match="until must be a frame from 1 to 30"):
        bake(scene(cache), resume=True, until=31)


def test_a_damaged_kept_checkpoint_is_reported_and_an_earlier_one_used(straight, tmp_path):
    cache = tmp_path / "c"
    bake(scene(cache))
    ck = bake_cache.kept_checkpoint_path(cache, 20)
    raw = bytearray(ck.read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    os.unlink(ck)  # a hard link to the latest of its time: replace it, do not write through it
    ck.write_bytes(bytes(raw))
    problems = verify_checkpoints(scene(cache))
    assert list(problems) == ["checkpoint/state_0020.npz"] and "damaged" in problems["checkpoint/state_0020.npz"]
    for f in range(21, END + 1):
        frame_path(cache, f).unlink()
    lines = []
    result = bake(scene(cache), resume=True, log=lines.append)
    assert result.resumed_from == 10, lines
    assert any("state_0020.npz" in line and "earlier checkpoint" in line for line in lines), lines
    assert grid_digests(cache, range(1, END + 1)) == grid_digests(straight, range(1, END + 1))


def test_free_removes_the_kept_checkpoints(tmp_path):
    cache = tmp_path / "c"
    bake(scene(cache, end=12, every=4))
    assert bake_cache.list_kept_checkpoints(cache) == [4, 8, 12]
    assert free_cache(cache) == 12 + 3 + 2  # frames, kept checkpoints, latest checkpoint and manifest
    assert not (cache / bake_cache.CHECKPOINT_DIR).exists() and list_frames(cache) == []


def test_checkpoint_every_zero_keeps_only_the_latest_and_rebakes_from_the_start(tmp_path):
    cache = tmp_path / "c"
    bake(scene(cache, end=12, every=0))
    assert bake_cache.list_kept_checkpoints(cache) == []
    plan = rebake_plan(scene(cache, end=12, every=0, new_from=8))
    assert (plan.first_frame, plan.checkpoint_frame) == (8, 0)
    assert plan.text == "probe keys changed from frame 8: re-bake 8-12 from the start"


def test_the_disk_cost_is_said_per_checkpoint():
    s = scene("/tmp/unused").with_resolution(64)
    assert describe_checkpoints(s) == "6.34 MB each, 3 kept"
    assert describe_checkpoints(s.with_resolution(192)) == "170 MB each, 3 kept"
    data = scene_json("/tmp/unused")
    data["frames"]["end"], data["resolution"] = 300, 192  # the last key holds after frame 30
    long = scene_from_dict(data)
    assert describe_checkpoints(long) == "170 MB each, 30 kept (5.11 GB)"


def test_frame_inputs_change_only_where_the_keys_do():
    """Keys at every frame: frame f reads keys f-1 and f only, so keys changed from 18 on change
    frames 18 on and nothing before; sparse keys make every frame between two keys read both."""
    a, b = scene("/tmp/a"), scene("/tmp/a", new_from=18)
    differs = [f for f in range(1, END + 1) if a.frame_inputs(f) != b.frame_inputs(f)]
    assert differs == list(range(18, END + 1))
    t = Trajectory([(0.0, np.eye(4)), (10.0, np.eye(4))])
    assert len(t.keys_between(3, 4)) == 2 and len(t.keys_between(10, 11)) == 1 and len(t.keys_between(-2, -1)) == 1
    moved = np.eye(4)
    moved[0, 3] = 0.1
    u = Trajectory([(0.0, np.eye(4)), (5.0, np.eye(4)), (10.0, moved)])
    v = Trajectory([(0.0, np.eye(4)), (5.0, np.eye(4)), (10.0, np.eye(4))])
    assert u.digest_between(4, 5) == v.digest_between(4, 5)  # key 10 does not shape frames up to 5
    assert u.digest_between(5, 6) != v.digest_between(5, 6)
    assert np.array_equal(u.pose(5.0).translation, np.zeros(3))


def test_a_manifest_from_before_inputs_were_recorded_still_resumes(tmp_path):
    """A cache baked by the previous version (no per-frame inputs): resume continues after its
    latest checkpoint when that matches the scene."""
    cache = tmp_path / "c"
    bake(scene(cache, end=12), until=6)
    manifest = bake_cache.read_manifest(cache)
    del manifest["inputs"]
    bake_cache.write_manifest(cache, manifest)
    plan = rebake_plan(scene(cache, end=12))
    assert (plan.kind, plan.first_frame, plan.checkpoint_frame) == ("legacy", 7, 6)
    assert bake(scene(cache, end=12), resume=True).resumed_from == 6
    assert json.loads((cache / bake_cache.MANIFEST_FILE).read_text())["inputs"]["version"] == 1


def test_the_command_line_plans_chains_and_verifies(tmp_path):
    """``bake --until``, ``bake --plan`` and ``bake --verify`` as a user or a farm task runs them."""
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene_json(tmp_path / "c", end=12, every=4)))

    def cli(*args):
        return subprocess.run([sys.executable, "-m", "hapticfluid", "bake", str(path), *args],
                              capture_output=True, text=True, timeout=300, env=dict(os.environ))

    first = cli("--resume", "--until", "6", "--quiet")
    assert first.returncode == 0, first.stderr
    plan = cli("--plan")
    assert plan.returncode == 1, plan.stderr
    assert plan.stdout.splitlines()[0] == "frames 1-6 baked: bake 7-12 from the checkpoint at 6"
    assert "checkpoints: every 4 frame(s), 47.3 KB each, 3 kept; kept now: 4, 6" in plan.stdout
    assert cli("--resume", "--quiet").returncode == 0
    done = cli("--plan")
    assert done.returncode == 0 and done.stdout.startswith("frames 1-12 are baked and up to date")
    verify = cli("--verify")
    assert verify.returncode == 0 and "and all 5 checkpoint(s)" in verify.stdout, verify.stdout
    kept = bake_cache.kept_checkpoint_path(tmp_path / "c", 8)
    data = kept.read_bytes()
    kept.unlink()
    kept.write_bytes(data[: len(data) // 2])
    verify = cli("--verify")
    assert verify.returncode == 1 and "checkpoint/state_0008.npz: checkpoint" in verify.stdout, verify.stdout
    bad = cli("--resume", "--until", "13")
    assert bad.returncode != 0 and "until must be a frame from 1 to 12" in bad.stderr, bad.stderr
