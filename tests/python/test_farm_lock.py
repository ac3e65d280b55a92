# SPDX-License-Identifier: GPL-3.0-or-later
"""Two farm workers handed the same bake task (shared storage): the cache's lock lets one bake
and refuses the other with a message naming the cache, and the first still completes."""

import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

from hapticfluid.bake.cache import LOCK_FILE, MANIFEST_FILE, list_frames

SCENE = Path(__file__).resolve().parents[1] / "farm" / "tiny_scene.json"


def _lock_is_held(cache: Path) -> bool:
    path = cache / LOCK_FILE
    if not path.exists():
        return False
    fd = os.open(path, os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)  # a lock taken here goes with the descriptor
    return False


def _worker(root: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "hapticfluid.farm", "bake", "--root", str(root),
                             "--resolution", "16", "--cache", "caches/shot", "scenes/shot.json"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env={**os.environ})


def test_two_workers_baking_one_cache_one_refuses_the_other_completes(tmp_path):
    (tmp_path / "scenes").mkdir()
    shutil.copy(SCENE, tmp_path / "scenes" / "shot.json")
    cache = tmp_path / "caches" / "shot"
    first = _worker(tmp_path)
    try:
        deadline = time.monotonic() + 120
        while not _lock_is_held(cache):  # the first worker is baking (it took the cache's lock)
            assert first.poll() is None, f"the first bake ended before taking the lock:\n{first.stdout.read()}"
            assert time.monotonic() < deadline, "the first bake never took the cache's lock"
            time.sleep(0.02)
        first.send_signal(signal.SIGSTOP)  # keep it mid-bake while the second worker starts
        try:
            second = _worker(tmp_path)
            out, _ = second.communicate(timeout=300)
        finally:
            first.send_signal(signal.SIGCONT)
        assert second.returncode == 1, out
        assert "another bake is running in the cache folder" in out and str(cache) in out, out
        out_first, _ = first.communicate(timeout=600)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    assert first.returncode == 0, out_first
    assert "bake finished: 4 frame(s)" in out_first, out_first
    manifest = json.loads((cache / MANIFEST_FILE).read_text())
    assert manifest["complete"] and manifest["frames_done"] == [1, 2, 3, 4]
    assert list_frames(cache) == [1, 2, 3, 4]
    assert len(manifest["sessions"]) == 1  # the refused worker left no session behind
