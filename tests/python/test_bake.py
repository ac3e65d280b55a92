# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake: OpenVDB round trip, state checkpoint, trajectory, resume after SIGKILL, cache errors."""

import json
import math
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid.bake import (BakeError, Trajectory, bake, frame_path, list_frames, load_scene,
                              read_manifest, scene_from_dict)
from hapticfluid.bake import cache as bake_cache
from hapticfluid.bake.openvdb_python import import_openvdb, missing_reason

vdb = import_openvdb()
if vdb is None:
    pytest.skip(missing_reason(), allow_module_level=True)


def read_grid(path, name, shape=None):
    grid = vdb.read(str(path), name)
    if shape is None:
        return grid
    zero = (0.0, 0.0, 0.0) if isinstance(grid, vdb.Vec3SGrid) else 0.0
    out = np.zeros(tuple(shape) + ((3,) if zero != 0.0 else ()), dtype=np.float32)
    grid.copyToArray(out, ijk=(0, 0, 0))
    return grid, out


@pytest.fixture(scope="module")
def plume():
    """A 24^3 plume a few steps old, with a moving probe: nonzero density, velocity, pressure."""
    sim = hf.Simulation(resolution=(24, 24, 24), domain_size=(1.2, 1.2, 1.2), origin=(-0.6, -0.6, 0.0),
                        heat_buoyancy=2.0, vorticity=0.3, open_top=True, pressure_iterations=20)
    sim.set_smoke_source((0.0, 0.0, 0.15), 0.12, density=1.0, temperature=8.0)
    for i in range(8):
        sim.set_probe((-0.2 + 0.02 * i, 0.0, 0.6), 0.15, velocity=(0.6, 0.0, 0.0))
        sim.step(0.04)
    yield sim
    sim.close()


# ---------------------------------------------------------------------------- writer

def test_the_same_grids_make_the_same_file_byte_for_byte(tmp_path):
    """OpenVDB draws a random UUID into every file's header; the writer replaces it with one
    derived from the file's content, so a frame baked again (resume, a farm chunk) is the same
    file, and other grids get another UUID. The file still reads back."""
    rng = np.random.default_rng(3)
    d = rng.random((8, 8, 8)).astype(np.float32)
    paths = [tmp_path / f"{i}.vdb" for i in range(3)]
    hf.write_vdb(str(paths[0]), d, 0.1)
    hf.write_vdb(str(paths[1]), d, 0.1)
    hf.write_vdb(str(paths[2]), d * 2, 0.1)
    a, b, c = (p.read_bytes() for p in paths)
    uuid = slice(21, 57)  # after the magic, three version numbers and the grid-offsets flag
    assert a == b and a[uuid] != c[uuid]
    assert a[uuid].decode().count("-") == 4 and a[uuid][14:15] == b"5"  # a name-based (SHA-1) UUID
    _, back = read_grid(paths[0], "density", (8, 8, 8))
    np.testing.assert_array_equal(back, d)


def test_vdb_round_trip_float_and_half(plume, tmp_path):
    d = plume.density()
    u, v, w = plume.velocity()
    p = plume.pressure(hydrostatic=False)
    h = plume.cell_size
    origin = tuple(float(x) for x in plume.origin)
    meta = {"frame": 7, "resolution": (24, 24, 24), "voxel_size": h, "note": "test", "flag": True}
    full, half = tmp_path / "full.vdb", tmp_path / "half.vdb"
    hf.write_vdb(str(full), d, h, origin, velocity=(u, v, w), pressure=p, metadata=meta)
    hf.write_vdb(str(half), d, h, origin, velocity=(u, v, w), pressure=p, half_float=True, compression="zip",
                 metadata=meta)
    assert sorted(os.listdir(tmp_path)) == ["full.vdb", "half.vdb"]  # no temporaries left

    grid, back = read_grid(full, "density", d.shape)
    assert grid.gridClass == "fog volume"
    np.testing.assert_array_equal(back, d)  # float32 exactly
    _, back_half = read_grid(half, "density", d.shape)
    np.testing.assert_allclose(back_half, d, rtol=2.0 ** -11, atol=1e-7)  # half: 11-bit significand
    assert np.any(back_half != d)  # it really was rounded
    assert half.stat().st_size < full.stat().st_size

    # Velocity at cell centres is the mean of each cell's two faces.
    vgrid, vel = read_grid(full, "velocity", d.shape)
    centred = np.stack([0.5 * (u[1:] + u[:-1]), 0.5 * (v[:, 1:] + v[:, :-1]), 0.5 * (w[:, :, 1:] + w[:, :, :-1])],
                       axis=-1)
    np.testing.assert_allclose(vel, centred, rtol=0, atol=1e-7)
    assert float(np.abs(centred).max()) > 0.05
    _, pb = read_grid(full, "pressure", d.shape)
    np.testing.assert_array_equal(pb, p)

    # Transform: voxel size h, cell (i, j, k)'s centre at origin + (i + 1/2) h.
    assert grid.transform.voxelSize() == pytest.approx((h, h, h), rel=1e-6)
    for ijk in ((0, 0, 0), (23, 5, 17)):
        world = grid.transform.indexToWorld(ijk)
        expected = [origin[a] + (ijk[a] + 0.5) * h for a in range(3)]
        assert world == pytest.approx(expected, abs=1e-6)
    lo, hi = vgrid.evalActiveVoxelBoundingBox()
    assert min(lo) >= 0 and max(hi) <= 23

    # Metadata on every grid and on the file.
    for name in ("density", "velocity", "pressure"):
        m = vdb.readGridMetadata(str(full), name).metadata
        assert m["frame"] == 7 and tuple(m["resolution"]) == (24, 24, 24) and m["note"] == "test"
        assert m["voxel_size"] == pytest.approx(h) and m["flag"] is True
    _, file_meta = vdb.readAll(str(full))
    assert file_meta["frame"] == 7
    assert vdb.readGridMetadata(str(half), "density").metadata["is_saved_as_half_float"] is True


def test_vdb_sparse_threshold(plume, tmp_path):
    d = plume.density()
    tol = 0.05
    path = tmp_path / "sparse.vdb"
    hf.write_vdb(str(path), d, plume.cell_size, tuple(plume.origin), tolerance=tol)
    grid, back = read_grid(path, "density", d.shape)
    above = np.abs(d) > tol
    assert 0 < np.count_nonzero(above) < d.size  # the threshold splits the field
    assert grid.activeVoxelCount() == np.count_nonzero(above)
    np.testing.assert_array_equal(back[above], d[above])
    assert np.all(back[~above] == 0.0)  # inactive voxels read as the background
    dense_path = tmp_path / "dense.vdb"
    hf.write_vdb(str(dense_path), d, plume.cell_size, tuple(plume.origin), tolerance=0.0)
    assert vdb.read(str(dense_path), "density").activeVoxelCount() == np.count_nonzero(d)


def test_vdb_writer_rejects_bad_input_and_leaves_no_file(tmp_path):
    d = np.zeros((8, 8, 8), np.float32)
    target = tmp_path / "x.vdb"
    with pytest.raises(hf.InvalidArgumentError, match=r"velocity x .* shape \(9, 8, 8\)"):
        hf.write_vdb(str(target), d, 0.1, velocity=(d, d, d))
    bad = d.copy()
    bad[1, 2, 3] = np.nan
    with pytest.raises(hf.InvalidArgumentError, match="non-finite"):
        hf.write_vdb(str(target), bad, 0.1)
    with pytest.raises(hf.InvalidArgumentError, match="compression"):
        hf.write_vdb(str(target), d, 0.1, compression="lzma")
    with pytest.raises(hf.InvalidArgumentError, match="voxel size"):
        hf.write_vdb(str(target), d, 0.0)
    with pytest.raises(hf.InvalidArgumentError, match="reserved"):
        hf.write_vdb(str(target), d, 0.1, metadata={"class": "x"})
    with pytest.raises(hf.HapticFluidError, match="cannot write into folder"):
        hf.write_vdb(str(tmp_path / "missing" / "x.vdb"), d, 0.1)
    assert not target.exists() and os.listdir(tmp_path) == []
    assert set(hf.vdb_compressions()) >= {"none", "zip", "blosc"}
    assert hf.openvdb_version().startswith("10.")


# ---------------------------------------------------------------------------- checkpoint

def _probe_path(i):
    return (0.3 + 0.03 * i, 0.5, 0.5), (0.75, 0.0, 0.0), (0.0, 0.0, 2.0)


def _make_sim():
    sim = hf.Simulation(resolution=(16, 16, 16), heat_buoyancy=1.5, vorticity=0.3, pressure_iterations=15,
                        advection="maccormack")
    sim.set_smoke_source((0.5, 0.5, 0.2), 0.15, density=1.0, temperature=6.0)
    return sim


def _run(sim, steps):
    for i in steps:
        c, v, w = _probe_path(i)
        sim.set_probe(c, 0.12, velocity=v, angular_velocity=w)
        sim.step(0.04)


def test_restored_state_continues_bit_identically():
    with _make_sim() as a, _make_sim() as b:
        _run(a, range(5))
        saved = a.state()
        assert saved["steps"] == 5 and saved["time"] == pytest.approx(0.2)
        _run(a, range(5, 10))
        b.set_state(saved)  # b never stepped: everything it carries comes from the dict
        assert b.steps == 5 and b.time == saved["time"]
        _run(b, range(5, 10))
        for name in ("velocity_x", "velocity_y", "velocity_z", "density", "temperature", "pressure"):
            np.testing.assert_array_equal(a.state()[name], b.state()[name], err_msg=name)
        assert float(a.density().max()) > 0.5
        # Without the pressure warm start the continuation differs (so the test can fail).
        broken = dict(saved)
        broken["pressure"] = np.zeros_like(saved["pressure"])
        b.set_state(broken)
        _run(b, range(5, 10))
        assert not np.array_equal(a.state()["velocity_x"], b.state()["velocity_x"])


def test_set_state_validates_before_changing_anything(small_sim):
    st = small_sim.state()
    before = small_sim.density().copy()
    bad = dict(st)
    bad["density"] = st["density"].astype(np.float64)
    with pytest.raises(hf.InvalidArgumentError, match="float32"):
        small_sim.set_state(bad)
    bad = dict(st)
    bad["velocity_y"] = np.zeros((16, 16, 16), np.float32)
    with pytest.raises(hf.InvalidArgumentError, match=r"velocity_y.*\(16, 17, 16\)"):
        small_sim.set_state(bad)
    bad = dict(st)
    del bad["temperature"]
    with pytest.raises(hf.InvalidArgumentError, match="missing 'temperature'"):
        small_sim.set_state(bad)
    bad = dict(st)
    bad["density"] = np.full((16, 16, 16), np.inf, np.float32)
    with pytest.raises(hf.InvalidArgumentError, match="non-finite"):
        small_sim.set_state(bad)
    np.testing.assert_array_equal(small_sim.density(), before)


# ---------------------------------------------------------------------------- trajectory

def _rot_z(deg, t=(0.0, 0.0, 0.0)):
    a = math.radians(deg)
    m = np.eye(4)
    m[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
    m[:3, 3] = t
    return m


def test_trajectory_interpolates_linearly_and_by_slerp():
    traj = Trajectory([(10, _rot_z(90, (1.0, 2.0, 0.0))), (0, _rot_z(0, (0.0, 0.0, 0.0)))])
    mid = traj.pose(5.0)
    np.testing.assert_allclose(mid.translation, (0.5, 1.0, 0.0), atol=1e-12)
    np.testing.assert_allclose(mid.matrix()[:3, :3], _rot_z(45)[:3, :3], atol=1e-12)  # slerp: half the angle
    np.testing.assert_allclose(traj.pose(-3).translation, (0, 0, 0))  # held before the first key
    np.testing.assert_allclose(traj.pose(99).matrix(), _rot_z(90, (1.0, 2.0, 0.0)), atol=1e-12)
    fps = 24.0
    m = traj.motion(2.0, 3.0, 1.0 / fps)  # one frame
    np.testing.assert_allclose(m.velocity, (0.1 * fps, 0.2 * fps, 0.0), atol=1e-9)  # m/s
    np.testing.assert_allclose(m.angular_velocity, (0.0, 0.0, math.radians(9.0) * fps), atol=1e-9)  # rad/s
    with pytest.raises(hf.InvalidArgumentError, match="frame 0"):
        Trajectory([(0, np.eye(4)), (0, np.eye(4))])


# ---------------------------------------------------------------------------- driver

def scene_dict(cache, frames=6, resolution=16, **overrides):
    d = {
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": resolution,
        "fluid": {"heat_buoyancy": 1.5, "vorticity": 0.3, "open_top": True, "pressure_iterations": 15},
        "source": {"centre": [0.5, 0.5, 0.2], "radius": 0.15, "temperature": 6.0},
        "probe": {"shape": "sphere", "radius": 0.12,
                  "keys": [{"frame": 0, "location": [0.3, 0.5, 0.55]},
                           {"frame": frames, "location": [0.7, 0.5, 0.55], "rotation": [0.7071068, 0, 0, 0.7071068]}]},
        "frames": {"start": 1, "end": frames, "fps": 24},
        "substeps": 2,
        "cache": {"directory": str(cache), "grids": ["density", "velocity", "pressure"], "tolerance": 0.0},
    }
    d.update(overrides)
    return d


def frame_arrays(cache, frame, shape=(16, 16, 16)):
    path = frame_path(cache, frame)
    return {name: read_grid(path, name, shape)[1] for name in ("density", "velocity", "pressure")}


def test_bake_writes_frames_manifest_and_reports_progress(tmp_path):
    scene = scene_from_dict(scene_dict(tmp_path / "c", frames=3))
    seen = []
    result = bake(scene, progress=seen.append)
    assert result.status == "finished" and result.frames_written == 3 and result.last_frame == 3
    assert list_frames(tmp_path / "c") == [1, 2, 3]
    manifest = read_manifest(tmp_path / "c")
    assert manifest["complete"] and manifest["frames_done"] == [1, 2, 3]
    assert manifest["scene"]["grid_resolution"] == [16, 16, 16]
    done = [p for p in seen if p.frame_finished]
    assert [p.frames_done for p in done] == [1, 2, 3] and done[-1].fraction == 1.0
    assert math.isnan(seen[0].eta_s) and done[0].eta_s > 0 and done[-1].eta_s == 0
    meta = vdb.readGridMetadata(str(frame_path(tmp_path / "c", 2)), "density").metadata
    assert meta["frame"] == 2 and meta["substeps"] == 2 and meta["hapticfluid_version"] == hf.__version__
    assert tuple(meta["resolution"]) == (16, 16, 16)
    assert meta["voxel_size"] == pytest.approx(1.0 / 16)


def test_bake_cancel_then_resume_matches_uninterrupted(tmp_path):
    full = scene_from_dict(scene_dict(tmp_path / "full", frames=4))
    bake(full)
    part = scene_from_dict(scene_dict(tmp_path / "part", frames=4))
    stop = threading.Event()

    def progress(p):  # cancel in the middle of frame 3 (after its first of 2 substeps)
        if p.frame == 3 and p.substep == 1 and not p.frame_finished:
            stop.set()

    first = bake(part, progress=progress, cancel=stop)
    assert first.status == "cancelled" and first.last_frame == 2 and list_frames(tmp_path / "part") == [1, 2]
    second = bake(part, resume=True)
    assert second.status == "finished" and second.resumed_from == 2 and second.frames_written == 2
    for frame in range(1, 5):
        a, b = frame_arrays(tmp_path / "full", frame), frame_arrays(tmp_path / "part", frame)
        for name in a:
            np.testing.assert_array_equal(a[name], b[name], err_msg=f"frame {frame} {name}")


def test_bake_killed_by_sigkill_resumes_to_identical_frames(tmp_path):
    frames = 8
    ref = scene_from_dict(scene_dict(tmp_path / "ref", frames=frames))
    bake(ref)
    scene_file = tmp_path / "scene.json"
    scene_file.write_text(json.dumps(scene_dict("killed", frames=frames)))
    env = dict(os.environ)
    cmd = [sys.executable, "-m", "hapticfluid", "bake", str(scene_file), "--quiet"]
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cache = tmp_path / "killed"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None and len(list_frames(cache)) < 3:
        time.sleep(0.005)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert proc.returncode == -signal.SIGKILL, "the bake ended before it could be killed: make it longer"
    done_before = list_frames(cache)
    assert 3 <= len(done_before) < frames
    resumed = subprocess.run(cmd + ["--resume"], env=env, capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    assert "bake finished" in resumed.stdout
    assert list_frames(cache) == list(range(1, frames + 1))
    leftovers = [p.name for p in cache.rglob("*") if p.name.endswith(".tmp")]
    assert leftovers == []
    for frame in range(1, frames + 1):
        a, b = frame_arrays(tmp_path / "ref", frame), frame_arrays(cache, frame)
        for name in a:
            np.testing.assert_array_equal(a[name], b[name], err_msg=f"frame {frame} {name}")


def test_damaged_or_foreign_checkpoint_is_refused(tmp_path):
    scene = scene_from_dict(scene_dict(tmp_path / "c", frames=2))
    bake(scene, until=1)
    ck = bake_cache.checkpoint_path(tmp_path / "c")
    good = ck.read_bytes()
    ck.write_bytes(good[: len(good) // 2])  # truncated, as a partial write would be
    with pytest.raises(BakeError, match="damaged or incomplete"):
        bake_cache.load_checkpoint(tmp_path / "c", scene.fingerprint())
    raw = bytearray(good)
    raw[len(raw) // 2] ^= 0xFF  # one flipped byte in the middle of an array
    ck.write_bytes(bytes(raw))
    with pytest.raises(BakeError, match="damaged|checksum"):
        bake_cache.load_checkpoint(tmp_path / "c", scene.fingerprint())
    # resume never uses it: it replays from the first frame to bake frame 2, and says why
    lines = []
    result = bake(scene, resume=True, log=lines.append)
    assert result.resumed_from is None and result.frames_written == 1, lines
    assert any("damaged" in line and "earlier checkpoint" in line for line in lines), lines
    ck.write_bytes(good)
    with pytest.raises(BakeError, match="other settings"):
        bake_cache.load_checkpoint(tmp_path / "c", scene.with_resolution(20).fingerprint())
    ck.unlink()
    with pytest.raises(BakeError, match="no checkpoint"):
        bake_cache.load_checkpoint(tmp_path / "c", scene.fingerprint())


def test_missing_or_unwritable_cache_fails_before_any_work(tmp_path):
    scene = scene_from_dict(scene_dict(tmp_path / "missing" / "deeper" / "cache", frames=2))
    with pytest.raises(BakeError, match="parent folder .* does not exist"):
        bake(scene)
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(BakeError, match="not a folder"):
        bake(scene_from_dict(scene_dict(blocker, frames=2)))
    if os.geteuid() == 0:  # root writes anywhere: use a folder the kernel refuses
        unwritable = Path("/proc/hapticfluid_cache")
    else:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        unwritable = ro / "cache"
    with pytest.raises(BakeError, match="not writable"):
        bake(scene_from_dict(scene_dict(unwritable, frames=2)))
    # The CLI says the same and exits 1.
    scene_file = tmp_path / "scene.json"
    scene_file.write_text(json.dumps(scene_dict(str(tmp_path / "nope" / "nope"), frames=2)))
    run = subprocess.run([sys.executable, "-m", "hapticfluid", "bake", str(scene_file)], capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 1 and "does not exist" in run.stderr


def test_scene_errors_name_the_key(tmp_path):
    with pytest.raises(hf.InvalidArgumentError, match="fluid.vorticty|unknown key"):
        scene_from_dict(scene_dict(tmp_path, fluid={"vorticty": 1.0}))
    with pytest.raises(hf.InvalidArgumentError, match="frames"):
        scene_from_dict({k: v for k, v in scene_dict(tmp_path).items() if k != "frames"})
    too_near_wall = scene_dict(tmp_path)
    too_near_wall["probe"]["keys"][1]["location"] = [0.95, 0.5, 0.55]
    with pytest.raises(hf.InvalidArgumentError, match=r"probe at frame 6 .*: probe sphere .* not inside the domain"):
        scene_from_dict(too_near_wall)
    small = scene_from_dict(scene_dict(tmp_path))
    with pytest.raises(hf.InvalidArgumentError, match="radius must be at least one cell"):
        small.with_resolution(8)  # cells of 0.125 m: the 0.12 m probe is under one cell
    missing = tmp_path / "nothing.json"
    run = subprocess.run([sys.executable, "-m", "hapticfluid", "bake", str(missing)], capture_output=True,
                         text=True, timeout=60)
    assert run.returncode == 2 and "cannot read the scene file" in run.stderr


def test_bake_uses_the_chosen_pressure_solver(tmp_path):
    with pytest.raises(hf.InvalidArgumentError, match="fluid.pressure_solver"):
        scene_from_dict(scene_dict(tmp_path, fluid={"pressure_solver": "sor"}))
    scene = scene_from_dict(scene_dict(tmp_path / "mg", frames=1,
                                       fluid={"pressure_solver": "multigrid", "pressure_iterations": 4}))
    from hapticfluid.bake import driver

    sim = driver.make_simulation(scene)
    try:
        assert sim.pressure_solver == hf.PressureSolver.multigrid and sim.pressure_iterations == 4
    finally:
        sim.close()
    with pytest.raises(hf.InvalidArgumentError, match="fluid.pressure_tolerance: pressure tolerance"):
        scene_from_dict(scene_dict(tmp_path / "tol", frames=1, fluid={"pressure_tolerance": 2.0}))


def test_bake_resolution_override_and_adaptive_substeps(tmp_path):
    scene = scene_from_dict(scene_dict(tmp_path / "a", frames=2, substeps="adaptive", cfl=0.5, max_substeps=6))
    hi = scene.with_resolution(24)
    assert hi.grid_resolution == (24, 24, 24) and hi.cell_size == pytest.approx(1 / 24)
    bake(hi)
    counts = [vdb.readGridMetadata(str(frame_path(tmp_path / "a", f)), "density").metadata["substeps"]
              for f in (1, 2)]
    # The probe moves 0.4 m in 6 frames at 24 fps (1.6 m/s): at least 1.6 / 24 / (0.5 / 24) = 3.2 -> 4 steps.
    assert all(4 <= n <= 6 for n in counts), counts


def test_example_scene_loads():
    root = Path(__file__).resolve().parents[2]
    scene = load_scene(root / "examples" / "bake_demo.json")
    assert scene.probe is not None and scene.frame_count == 44
    assert scene.cache_dir.resolve() == (root / "out" / "bake_demo_cache").resolve()  # relative to the file


def test_bake_benchmark_quick_runs(tmp_path, capsys):
    from hapticfluid.bench import bake as bench
    from hapticfluid.bench import report

    out = tmp_path / "bake.json"
    assert report.section_main("bake", bench.run, ["--quick", "--json", str(out)]) == 0
    assert [p.name for p in tmp_path.iterdir()] == ["bake.json"]  # written atomically, no temporary left
    res = json.loads(out.read_text())["sections"]["bake"]
    assert res["columns"][0] == "resolution" and len(res["rows"]) == 8
    col = {c: i for i, c in enumerate(res["columns"])}
    # Timings measured (finite; the table rounds them, so a fast one may read 0); sizes are bytes written.
    assert all(row[col["status"]] == "finished" and row[col["last frame KiB"]] > 0
               and all(math.isfinite(row[col[c]]) and row[col[c]] >= 0 for c in ("s/frame", "first frame s"))
               for row in res["rows"]), res["rows"]
    by_key = {(r[0], r[1], r[2]): r for r in res["rows"]}
    # Half floats make the files with velocity and pressure (dense fields) smaller.
    assert by_key[("24^3", "density+velocity+pressure", "half")][6] < \
        by_key[("24^3", "density+velocity+pressure", "float")][6]
    json.dumps(res)


def mesh_probe_scene(cache, frames=4):
    from hapticfluid import meshes

    vertices, triangles = meshes.box((0.24, 0.16, 0.16))
    d = scene_dict(cache, frames=frames)
    d["probe"] = {"shape": "mesh", "vertices": np.asarray(vertices).tolist(),
                  "triangles": np.asarray(triangles).tolist(),
                  "keys": [{"frame": 0, "location": [0.3, 0.5, 0.55]},
                           {"frame": frames, "location": [0.7, 0.5, 0.55],
                            "rotation": [0.9238795, 0.0, 0.0, 0.3826834]}]}  # 45 degrees about z
    return d


def test_mesh_probe_bake_resumes_identically(tmp_path):
    full = scene_from_dict(mesh_probe_scene(tmp_path / "full"))
    assert full.probe.shape == "mesh" and full.fingerprint()["probe"]["mesh_sha256"]
    bake(full)
    part = scene_from_dict(mesh_probe_scene(tmp_path / "part"))
    stop = threading.Event()
    first = bake(part, progress=lambda p: p.frame == 2 and not p.frame_finished and stop.set(), cancel=stop)
    assert first.status == "cancelled" and first.last_frame == 1
    bake(part, resume=True)
    for frame in range(1, 5):
        a, b = frame_arrays(tmp_path / "full", frame), frame_arrays(tmp_path / "part", frame)
        for name in a:
            np.testing.assert_array_equal(a[name], b[name], err_msg=f"frame {frame} {name}")
    # The box pushed the fluid: the velocity field is far from rest.
    assert float(np.abs(frame_arrays(tmp_path / "full", 2)["velocity"]).max()) > 0.3


def test_refused_trajectory_fails_before_work_and_keeps_the_old_bake(tmp_path):
    cache = tmp_path / "c"
    bake(scene_from_dict(scene_dict(cache, frames=2)))
    before = {f: frame_path(cache, f).read_bytes() for f in (1, 2)}
    open_mesh = mesh_probe_scene(cache, frames=2)
    open_mesh["probe"]["triangles"] = open_mesh["probe"]["triangles"][:-1]  # a hole: not closed
    with pytest.raises(hf.InvalidArgumentError, match="refused at frame 1"):
        bake(scene_from_dict(open_mesh))
    assert {f: frame_path(cache, f).read_bytes() for f in (1, 2)} == before
