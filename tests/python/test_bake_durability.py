"""Crash safety and resume bookkeeping of the bake cache (review fixes)."""

import os
import stat

import pytest

from hapticfluid.bake import cache as bake_cache


def test_atomic_write_flushes_the_folder_after_the_rename(tmp_path, monkeypatch):
    target = tmp_path / "manifest.json"
    real_fsync = os.fsync
    calls = []

    def recording_fsync(fd):
        st = os.fstat(fd)
        calls.append((stat.S_ISDIR(st.st_mode), st.st_ino, target.exists()))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", recording_fsync)
    bake_cache.atomic_write(target, lambda f: f.write("{}"))
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
        bake_cache.atomic_write(target, fail, binary=True)
    assert list(tmp_path.iterdir()) == []
