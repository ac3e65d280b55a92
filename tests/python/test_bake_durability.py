# SPDX-License-Identifier: GPL-3.0-or-later
"""Crash safety and resume bookkeeping of the bake cache (review fixes)."""

import os
import stat

import pytest

from hapticfluid import files


def test_atomic_write_flushes_the_folder_after_the_rename(tmp_path, monkeypatch):
    target = tmp_path / "manifest.json"
    real_fsync = os.fsync
    calls = []

    def recording_fsync(fd):
        st = os.fstat(fd)
        calls.append((stat.S_ISDIR(st.st_mode), st.st_ino, target.exists()))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", recording_fsync)
    files.atomic_write(target, lambda f: f.write("{}"))
    assert target.read_text() == "{}"
    folder_ino = os.stat(tmp_path).st_ino
    # the file's data before the rename, then the folder once the new name is in it
    assert calls[0][0] is False and calls[0][2] is False
    assert (True, folder_ino, True) in calls, calls


def test_atomic_write_failure_leaves_no_file_and_no_temporary(tmp_path):
    target = tmp_path / "state.npz"

    def fail(_f):
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        files.atomic_write(target, fail, binary=True)
    assert list(tmp_path.iterdir()) == []


def _small_scene(cache, frames):
    from hapticfluid.bake import scene_from_dict

    return scene_from_dict({
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 8,
        "fluid": {"pressure_iterations": 4},
        "source": {"centre": [0.5, 0.5, 0.3], "radius": 0.2, "temperature": 5.0},
        "frames": {"start": 1, "end": frames, "fps": 24},
        "substeps": 1,
        "cache": {"directory": str(cache)},
    })


def test_resuming_a_finished_bake_keeps_the_manifest_complete(tmp_path):
    from hapticfluid.bake import bake, read_manifest

    scene = _small_scene(tmp_path / "c", 2)
    assert bake(scene).last_frame == 2
    assert read_manifest(tmp_path / "c")["complete"] is True
    before = (tmp_path / "c" / "hapticfluid_bake.json").read_bytes()
    again = bake(scene, resume=True)  # nothing to do: the cache is left as it was, manifest included
    assert again.frames_written == 0 and again.last_frame == 2 and again.resumed_from is None
    assert again.plan.kind == "complete"
    assert (tmp_path / "c" / "hapticfluid_bake.json").read_bytes() == before
    manifest = read_manifest(tmp_path / "c")
    assert manifest["complete"] is True and manifest["frames_done"] == [1, 2]
    assert [s["resumed_from"] for s in manifest["sessions"]] == [None]


def test_a_sheared_key_is_refused_not_silently_changed():
    import numpy as np

    import hapticfluid as hf
    from hapticfluid.bake import Trajectory

    # rotated by 30 degrees about z, then scaled 2x along world x: its axes are not perpendicular
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    sheared = np.eye(4)
    sheared[:3, :3] = np.diag([2.0, 1.0, 1.0]) @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    with pytest.raises(hf.InvalidArgumentError, match="sheared"):
        Trajectory([(1.0, sheared)])
    # rotation, non-uniform scale and a mirror without shear still round-trip exactly
    good = np.eye(4)
    good[:3, :3] = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ np.diag([-2.0, 0.5, 3.0])
    good[:3, 3] = (0.1, 0.2, 0.3)
    np.testing.assert_allclose(Trajectory([(1.0, good)]).pose(1.0).matrix(), good, atol=1e-12)


@pytest.mark.parametrize("value", [2 ** 70, (1, 2, 2 ** 40), (1.0, "a", 2.0)])
def test_vdb_metadata_that_cannot_be_stored_is_a_clear_invalid_argument(tmp_path, value):
    import numpy as np

    import hapticfluid as hf

    target = tmp_path / "f.vdb"
    with pytest.raises(hf.InvalidArgumentError, match="metadata 'bad'"):
        hf.write_vdb(str(target), np.zeros((2, 2, 2), np.float32), 0.1, metadata={"ok": 1, "bad": value})
    assert list(tmp_path.iterdir()) == []


def test_resume_hint_keeps_the_cache_folder_and_resolution(tmp_path):
    import argparse
    import shlex

    from hapticfluid.bake.command import resume_command

    args = argparse.Namespace(scene="my scene.json", resolution=48, cache=str(tmp_path / "other cache"))
    words = shlex.split(resume_command(args))
    assert words[:6] == ["python3", "-m", "hapticfluid", "bake", "my scene.json", "--resume"]
    assert words[words.index("--resolution") + 1] == "48"
    assert words[words.index("--cache") + 1] == str(tmp_path / "other cache")
    plain = shlex.split(resume_command(argparse.Namespace(scene="s.json", resolution=None, cache=None)))
    assert "--cache" not in plain and "--resolution" not in plain


def test_a_frame_rate_the_engine_cannot_step_is_refused_when_the_scene_loads(tmp_path):
    import hapticfluid as hf
    from hapticfluid.bake import bake, list_frames, scene_from_dict

    def scene(**overrides):
        d = {"domain": {"size": [1.0, 1.0, 1.0]}, "resolution": 8, "frames": {"start": 1, "end": 1, "fps": 24},
             "substeps": 1, "cache": {"directory": str(tmp_path / "c")}}
        d.update(overrides)
        return d

    assert hf.MIN_TIME_STEP_S == pytest.approx(1e-6) and hf.MAX_TIME_STEP_S == pytest.approx(10.0)
    bake(scene_from_dict(scene()))  # an earlier bake that a refused one must not free
    # 0.05 fps, 1 substep: 20 s steps, twice the engine's longest step
    with pytest.raises(hf.InvalidArgumentError, match=r"frames\.fps.*20 s"):
        scene_from_dict(scene(frames={"start": 1, "end": 1, "fps": 0.05}))
    # adaptive may take a single 20 s step too, though max_substeps alone would be fine
    with pytest.raises(hf.InvalidArgumentError, match=r"frames\.fps.*adaptive"):
        scene_from_dict(scene(frames={"start": 1, "end": 1, "fps": 0.05}, substeps="adaptive", max_substeps=4))
    with pytest.raises(hf.InvalidArgumentError, match=r"frames\.fps.*at least"):
        scene_from_dict(scene(frames={"start": 1, "end": 1, "fps": 1e5}, substeps=20))
    scene_from_dict(scene(frames={"start": 1, "end": 1, "fps": 0.2}, substeps=2))  # 2.5 s steps are fine
    assert list_frames(tmp_path / "c") == [1]


def test_mesh_triangle_indices_that_are_not_integers_are_refused():
    import hapticfluid as hf
    from hapticfluid.bake import scene_from_dict

    def scene(triangles):
        vertices = [[0.4, 0.4, 0.4], [0.6, 0.4, 0.4], [0.4, 0.6, 0.4], [0.4, 0.4, 0.6]]
        return {"domain": {"size": [1.0, 1.0, 1.0]}, "resolution": 16, "frames": {"start": 1, "end": 1},
                "cache": {"directory": "c"},
                "probe": {"shape": "mesh", "vertices": vertices, "triangles": triangles,
                          "keys": [{"frame": 1, "location": [0.0, 0.0, 0.0]}]}}

    good = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    assert scene_from_dict(scene(good)).probe.triangles.tolist() == good
    for bad in ([[0, 2, 1.5], [0, 1, 3], [0, 3, 2], [1, 2, 3]],   # was truncated to 1
                [[0, 2, True], [0, 1, 3], [0, 3, 2], [1, 2, 3]]):  # booleans are not indices
        with pytest.raises(hf.InvalidArgumentError, match=r"probe\.triangles: vertex indices must be integers"):
            scene_from_dict(scene(bad))


def test_probe_keys_of_the_other_shape_are_refused_not_ignored():
    import hapticfluid as hf
    from hapticfluid.bake import scene_from_dict

    base = {"domain": {"size": [1.0, 1.0, 1.0]}, "resolution": 16, "frames": {"start": 1, "end": 1},
            "cache": {"directory": "c"}}
    keys = [{"frame": 1, "location": [0.5, 0.5, 0.5]}]
    vertices = [[-0.1, -0.1, -0.1], [0.1, -0.1, -0.1], [-0.1, 0.1, -0.1], [-0.1, -0.1, 0.1]]
    triangles = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    with pytest.raises(hf.InvalidArgumentError, match=r"scene probe: a sphere probe takes no \['triangles', 'vertices'\]"):
        scene_from_dict({**base, "probe": {"radius": 0.1, "vertices": vertices, "triangles": triangles, "keys": keys}})
    with pytest.raises(hf.InvalidArgumentError, match=r"scene probe: a mesh probe takes no \['radius'\]"):
        scene_from_dict({**base, "probe": {"shape": "mesh", "radius": 0.3, "vertices": vertices,
                                           "triangles": triangles, "keys": keys}})
    assert scene_from_dict({**base, "probe": {"shape": "mesh", "vertices": vertices, "triangles": triangles,
                                              "keys": keys}}).probe.shape == "mesh"


def test_frames_no_bake_wrote_are_never_deleted(tmp_path):
    from hapticfluid.bake import BakeError, bake, free_cache

    cache = tmp_path / "mantaflow_cache"
    (cache / "data").mkdir(parents=True)
    foreign = cache / "data" / "fluid_data_0001.vdb"  # Blender's own fluid cache has this layout
    foreign.write_bytes(b"someone else's frame")
    with pytest.raises(BakeError, match="no hapticfluid_bake.json.*not deleted"):
        bake(_small_scene(cache, 1))
    with pytest.raises(BakeError, match="not deleted"):
        free_cache(cache)
    assert foreign.read_bytes() == b"someone else's frame"
    # our own bake in the same place is freed and re-baked as before
    foreign.unlink()
    bake(_small_scene(cache, 1))
    assert bake(_small_scene(cache, 1)).frames_written == 1
    assert free_cache(cache) >= 3 and not (cache / "data").exists()


def test_a_bake_cancelled_before_its_first_step_keeps_the_earlier_bake(tmp_path):
    from hapticfluid.bake import bake, list_frames, read_manifest, scene_from_dict

    def scene(frames):
        return scene_from_dict({
            "domain": {"size": [1.0, 1.0, 1.0]}, "resolution": 8, "fluid": {"pressure_iterations": 2},
            "probe": {"radius": 0.15, "keys": [{"frame": 0, "location": [0.35, 0.5, 0.5]},
                                               {"frame": frames, "location": [0.65, 0.5, 0.5]}]},
            "frames": {"start": 1, "end": frames, "fps": 24}, "substeps": 1,
            "cache": {"directory": str(tmp_path / "c")}})

    assert bake(scene(2)).last_frame == 2
    before = {p.name: p.read_bytes() for p in (tmp_path / "c" / "data").iterdir()}
    calls = []

    def cancel_during_the_trajectory_check():
        calls.append(1)
        return len(calls) >= 3

    result = bake(scene(40), cancel=cancel_during_the_trajectory_check)
    assert result.status == "cancelled" and result.frames_written == 0 and result.last_frame is None
    assert len(calls) < 40  # it stopped checking the 40-frame trajectory at once
    assert {p.name: p.read_bytes() for p in (tmp_path / "c" / "data").iterdir()} == before
    assert list_frames(tmp_path / "c") == [1, 2] and read_manifest(tmp_path / "c")["frames_done"] == [1, 2]


def test_a_second_bake_or_free_in_a_folder_being_baked_is_refused(tmp_path):
    import subprocess
    import sys
    import textwrap

    from hapticfluid.bake import BakeError, bake, free_cache, list_frames

    scene = _small_scene(tmp_path / "c", 1)
    bake(scene)
    # another process holds the folder's lock, as a running bake does
    holder = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import sys, time
        from hapticfluid.bake.cache import bake_lock
        with bake_lock({str(tmp_path / "c")!r}):
            print("locked", flush=True)
            sys.stdin.readline()
        """)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
        env={**os.environ})
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(BakeError, match="another bake is running"):
            bake(scene)
        with pytest.raises(BakeError, match="another bake is running"):
            free_cache(tmp_path / "c")
        assert list_frames(tmp_path / "c") == [1]
    finally:
        holder.communicate("\n", timeout=60)
    assert bake(scene).frames_written == 1  # the lock went with the holder


def test_a_checkpoint_write_that_hits_the_file_size_limit_fails_cleanly(tmp_path):
    """File too large (as disk full): one OSError, no temporary left, and no "seek of closed
    file" from np.savez's zip finalised after atomic_write closed the file."""
    import subprocess
    import sys
    import textwrap

    (tmp_path / "checkpoint").mkdir()
    script = textwrap.dedent("""
        import resource, signal, sys
        import numpy as np
        from hapticfluid.bake import cache
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # write() then fails with EFBIG
        state = {"density": np.ones((64, 64, 64), np.float32), "time": 1.0, "steps": 3}
        resource.setrlimit(resource.RLIMIT_FSIZE, (200000, 200000))
        try:
            cache.save_checkpoint(sys.argv[1], 1, state, {"a": 1})
        except OSError as exc:
            print("OSError", exc.errno)
    """)
    proc = subprocess.run([sys.executable, "-c", script, str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "OSError 27", proc.stdout  # EFBIG
    assert proc.stderr == "", proc.stderr  # used to print "Exception ignored in ... seek of closed file"
    assert list((tmp_path / "checkpoint").iterdir()) == []
