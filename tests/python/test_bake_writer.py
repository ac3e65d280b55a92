# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake's writer thread (bake/writer.py): frames written in order beside the stepping, a
bounded queue, and a failed write surfacing as the bake's error naming the frame, with the
cache left resumable to the same bits."""

import threading

import numpy as np
import pytest

from hapticfluid.bake import writer as _writer
from hapticfluid.bake.cache import BakeError


def _job(frame):
    return _writer.FrameJob(frame=frame, substeps=1, state={}, step_s=0.0)


def test_frames_are_written_in_order_and_reported_once():
    seen = []
    w = _writer.FrameWriter(lambda job: seen.append(job.frame))
    for f in range(1, 6):
        w.put(_job(f))
    w.close()
    w.check()
    assert seen == [1, 2, 3, 4, 5]
    assert [d.frame for d in w.finished()] == [1, 2, 3, 4, 5]
    assert w.finished() == []


def test_the_queue_holds_at_most_depth_frames_beside_the_one_being_written():
    release = threading.Event()
    started = []

    def slow(job):
        started.append(job.frame)
        release.wait(30)

    w = _writer.FrameWriter(slow, depth=1)
    w.put(_job(1))  # taken by the writer, which then waits
    w.put(_job(2))  # waits in the queue
    third = threading.Thread(target=w.put, args=(_job(3),))
    third.start()
    third.join(0.5)
    assert third.is_alive()  # blocked: two frames are in flight already
    assert started == [1]
    release.set()
    third.join(30)
    assert not third.is_alive()
    w.close()
    assert started == [1, 2, 3]


def test_abort_when_drops_the_frames_not_yet_being_written():
    """The bake's 'stop at once' (a second Ctrl-C sets a flag the writer polls): the frame being
    written lands whole, the queued one and a put that waits for room are dropped."""
    release = threading.Event()
    started, stop = [], []

    def slow(job):
        started.append(job.frame)
        release.wait(30)

    w = _writer.FrameWriter(slow, depth=1, abort_when=lambda: bool(stop))
    w.put(_job(1))  # being written
    w.put(_job(2))  # queued
    third = threading.Thread(target=w.put, args=(_job(3),))
    third.start()
    third.join(0.3)
    assert third.is_alive()  # waits for room
    stop.append(True)
    third.join(5)  # put sees the flag within its poll and drops frame 3
    assert not third.is_alive()
    release.set()
    w.close()
    w.check()
    assert started == [1]
    assert [d.frame for d in w.finished()] == [1]


def test_ctrl_c_while_closing_aborts_but_never_leaves_the_writer_running():
    """Issue 19: Ctrl-C storms on the bake ended with 'terminate called without an active
    exception' (exit -6): a KeyboardInterrupt raised inside close() left the daemon writer in a
    frame's (native) write as the interpreter exited. Now close() waits for the thread, drops
    the queued frames, and raises the KeyboardInterrupt after."""
    import os
    import signal

    writing = threading.Event()
    release = threading.Event()
    seen, done = [], []

    def slow(job):
        seen.append(job.frame)
        writing.set()
        release.wait(30)
        done.append(job.frame)

    w = _writer.FrameWriter(slow, depth=1)
    w.put(_job(1))  # being written
    w.put(_job(2))  # queued: dropped by the abort the Ctrl-C turns the close into
    assert writing.wait(30)

    def ctrl_c_then_release():
        os.kill(os.getpid(), signal.SIGINT)  # Python's default handler: KeyboardInterrupt in close()
        threading.Timer(0.3, release.set).start()

    # Python's own SIGINT handler, whatever this process inherited (a job started in the
    # background by a non-interactive shell ignores SIGINT, and Python then keeps it ignored).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        threading.Timer(0.2, ctrl_c_then_release).start()
        with pytest.raises(KeyboardInterrupt):
            w.close()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert done == [1]  # close() returned only once the frame being written was written
    assert seen == [1]  # and frame 2 was dropped


def test_a_failed_write_names_the_frame_and_drops_what_follows():
    seen = []

    def write(job):
        if job.frame == 2:
            raise OSError(28, "No space left on device")
        seen.append(job.frame)

    w = _writer.FrameWriter(write, depth=2)
    for f in (1, 2, 3):
        w.put(_job(f))
    w.close()
    with pytest.raises(BakeError, match=r"writing frame 2 failed \(OSError: .*No space left.*resume") as info:
        w.check()
    assert isinstance(info.value.__cause__, OSError)
    assert seen == [1]  # frame 3 never runs past the failed frame 2
    assert [d.frame for d in w.finished()] == [1]


def _scene(cache, frames):
    from hapticfluid.bake import scene_from_dict

    return scene_from_dict({
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 10,
        "fluid": {"pressure_iterations": 4, "vorticity": 0.3, "heat_buoyancy": 1.0},
        "source": {"centre": [0.5, 0.5, 0.3], "radius": 0.2, "temperature": 5.0},
        "probe": {"shape": "sphere", "radius": 0.15,
                  "keys": [{"frame": 0, "location": [0.3, 0.5, 0.5]},
                           {"frame": frames, "location": [0.7, 0.5, 0.5]}]},
        "frames": {"start": 1, "end": frames, "fps": 24},
        "substeps": 1,
        "cache": {"directory": str(cache), "grids": ["density", "velocity"], "half_float": True},
    })


def test_a_write_error_mid_bake_is_the_bakes_error_and_resume_gives_the_same_bits(tmp_path, monkeypatch):
    from hapticfluid.bake import bake, driver, read_manifest
    from hapticfluid.bake.cache import list_frames, load_checkpoint

    reference = _scene(tmp_path / "ref", 4)
    bake(reference)
    _, expected = load_checkpoint(tmp_path / "ref", reference.fingerprint())

    scene = _scene(tmp_path / "c", 4)
    real = driver.write_frame

    def failing(scene_, state, frame, substeps):
        if frame == 3:
            raise OSError(28, "No space left on device")
        return real(scene_, state, frame, substeps)

    monkeypatch.setattr(driver, "write_frame", failing)
    lines = []
    with pytest.raises(BakeError, match=r"writing frame 3 failed .*No space left"):
        bake(scene, log=lines.append)
    assert list_frames(tmp_path / "c") == [1, 2]
    manifest = read_manifest(tmp_path / "c")
    assert manifest["last_frame"] == 2 and manifest["frames_done"] == [1, 2] and not manifest["complete"]
    assert sum(line.startswith("frame ") for line in lines) == 2  # frames 1 and 2 were reported

    monkeypatch.setattr(driver, "write_frame", real)
    result = bake(scene, resume=True)
    assert result.resumed_from == 2 and result.last_frame == 4
    assert list_frames(tmp_path / "c") == [1, 2, 3, 4]
    _, state = load_checkpoint(tmp_path / "c", scene.fingerprint())  # the state after frame 4
    assert sorted(state) == sorted(expected)
    for name, value in expected.items():
        np.testing.assert_array_equal(state[name], value, err_msg=name)


def _state(rng):
    def field(shape):
        return np.asfortranarray(rng.standard_normal(shape).astype(np.float32))  # as Simulation.state()

    return {"velocity_x": field((7, 6, 5)), "velocity_y": field((6, 7, 5)), "velocity_z": field((6, 6, 6)),
            "density": field((6, 6, 5)), "pressure": field((6, 6, 5)), "time": 0.25, "steps": 6}


def test_the_checkpoint_is_read_back_exactly_and_its_crc_catches_damage(tmp_path):
    import json
    import zipfile

    from hapticfluid.bake.cache import checkpoint_path, load_checkpoint, save_checkpoint

    state = _state(np.random.default_rng(1))
    (tmp_path / "checkpoint").mkdir()
    save_checkpoint(tmp_path, 3, state, {"a": 1})
    path = checkpoint_path(tmp_path)
    with zipfile.ZipFile(path) as z:
        assert z.namelist()[-1] == "meta.npy"
        assert z.testzip() is None  # every member's CRC-32 matches its bytes
        meta = json.loads(np.load(z.open("meta.npy")).tobytes())
        member = z.getinfo("density.npy")
        data_at = member.header_offset + len(member.FileHeader(zip64=True))  # the member's bytes
    assert meta["format"] == 3
    for name in ("velocity_x", "density"):
        info = meta["arrays"][name]
        assert info["order"] == "F" and "sha256" not in info  # the array as it lies in memory
    frame, back = load_checkpoint(tmp_path, {"a": 1})
    assert frame == 3 and back["time"] == 0.25 and back["steps"] == 6
    for name, value in state.items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(back[name], value, err_msg=name)
            assert back[name].flags.f_contiguous
    # one flipped bit in the density's data: the zip's CRC-32 refuses it
    raw = bytearray(path.read_bytes())
    raw[data_at + member.file_size - 5] ^= 0x01
    path.write_bytes(bytes(raw))
    with pytest.raises(BakeError, match="damaged or incomplete.*CRC"):
        load_checkpoint(tmp_path, {"a": 1})


def test_a_format_2_checkpoint_still_resumes_and_its_digest_is_checked(tmp_path):
    """Format 2: each array's SHA-256 in its memory order beside the zip's CRC-32."""
    import hashlib
    import json

    from hapticfluid.bake.cache import checkpoint_path, load_checkpoint, settings_digest

    arrays = {k: v for k, v in _state(np.random.default_rng(3)).items() if isinstance(v, np.ndarray)}

    def write(digests):
        meta = {"format": 2, "frame": 4, "scalars": {"time": 0.25, "steps": 6},
                "settings_sha256": settings_digest({"a": 1}), "settings": {"a": 1},
                "arrays": {k: {"sha256": digests[k], "order": "F", "shape": list(a.shape), "dtype": str(a.dtype)}
                           for k, a in arrays.items()}}
        with open(checkpoint_path(tmp_path), "wb") as f:
            np.savez(f, meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8), **arrays)

    (tmp_path / "checkpoint").mkdir()
    right = {k: hashlib.sha256(a.tobytes(order="F")).hexdigest() for k, a in arrays.items()}
    write(right)
    frame, back = load_checkpoint(tmp_path, {"a": 1})
    assert frame == 4
    for name, value in arrays.items():
        np.testing.assert_array_equal(back[name], value, err_msg=name)
    write({**right, "pressure": hashlib.sha256(b"other").hexdigest()})  # a sound zip, a wrong digest
    with pytest.raises(BakeError, match="'pressure' does not match its checksum"):
        load_checkpoint(tmp_path, {"a": 1})


def test_a_format_1_checkpoint_still_resumes(tmp_path):
    """Format 1 (before the writer thread): C-order copies, digests of the C-order bytes."""
    import hashlib
    import json

    from hapticfluid.bake.cache import checkpoint_path, load_checkpoint, settings_digest

    state = _state(np.random.default_rng(2))
    arrays = {k: v for k, v in state.items() if isinstance(v, np.ndarray)}
    meta = {"format": 1, "frame": 2, "scalars": {"time": 0.25, "steps": 6},
            "settings_sha256": settings_digest({"a": 1}), "settings": {"a": 1},
            "arrays": {k: {"sha256": hashlib.sha256(np.ascontiguousarray(a)).hexdigest(), "shape": list(a.shape),
                           "dtype": str(a.dtype), "fortran": True} for k, a in arrays.items()}}
    (tmp_path / "checkpoint").mkdir()
    with open(checkpoint_path(tmp_path), "wb") as f:
        np.savez(f, meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8),
                 **{k: np.ascontiguousarray(a) for k, a in arrays.items()})
    frame, back = load_checkpoint(tmp_path, {"a": 1})
    assert frame == 2
    for name, value in arrays.items():
        np.testing.assert_array_equal(back[name], value, err_msg=name)
    # and a damaged format-1 array is still refused
    arrays["density"][0, 0, 0] += 1.0
    with open(checkpoint_path(tmp_path), "wb") as f:
        np.savez(f, meta=np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8),
                 **{k: np.ascontiguousarray(a) for k, a in arrays.items()})
    with pytest.raises(BakeError, match="'density' does not match its checksum"):
        load_checkpoint(tmp_path, {"a": 1})
