# SPDX-License-Identifier: GPL-3.0-or-later
"""The bake CLI turns every bad scene file, path and manifest into one clear error line (exit 2
for the scene, 1 for the cache), never a traceback; write_vdb refuses a path with a NUL."""

import json

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid.bake import cache as bake_cache
from hapticfluid.cli import main


def good_scene(cache):
    return {
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 16,
        "frames": {"start": 1, "end": 2, "fps": 24},
        "cache": {"directory": str(cache)},
    }


def run(capsys, *argv):
    rc = main(["bake", *map(str, argv)])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return rc, out, err


@pytest.mark.parametrize("content, message", [
    (b'{"resolution": 16, "comment": "\xff"}', "not UTF-8 text"),
    (b"[" * 100000, "nests JSON too deeply"),
    (b'{"resolution": ' + b"1" * 5000 + b"}", "cannot be read as JSON"),
], ids=["not-utf8", "deep-json", "5000-digit-int"])
def test_unreadable_scene_files_are_clear_errors(tmp_path, capsys, content, message):
    scene = tmp_path / "scene.json"
    scene.write_bytes(content)
    rc, _, err = run(capsys, scene)
    assert rc == 2 and message in err and "scene.json" in err, err


@pytest.mark.parametrize("change, message", [
    (lambda d: d["cache"].update(directory="cache\u0000x"), "cache.directory"),
    (lambda d: d.update(probe={"shape": [], "keys": [{"frame": 1, "location": [0.5, 0.5, 0.5]}]}), "probe.shape"),
    (lambda d: d.update(probe={"shape": {}, "keys": [{"frame": 1, "location": [0.5, 0.5, 0.5]}]}), "probe.shape"),
    (lambda d: d.update(resolution=2 ** 31), "less than 2^31"),
    (lambda d: d.update(resolution=10 ** 40), "less than 2^31"),
], ids=["nul-in-cache", "shape-list", "shape-object", "resolution-2^31", "resolution-1e40"])
def test_bad_scene_values_are_clear_errors(tmp_path, capsys, change, message):
    d = good_scene(tmp_path / "cache")
    change(d)
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(d))
    rc, _, err = run(capsys, scene)
    assert rc == 2 and message in err, err


def test_a_resolution_option_of_2_to_the_31_is_a_clear_error(tmp_path, capsys):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(good_scene(tmp_path / "cache")))
    rc, _, err = run(capsys, scene, "--resolution", 2 ** 31)
    assert rc == 2 and "less than 2^31" in err, err


def test_a_nul_in_the_cache_option_is_a_clear_error(tmp_path, capsys):
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(good_scene(tmp_path / "cache")))
    rc, _, err = run(capsys, scene, "--cache", str(tmp_path / "a\u0000b"))
    assert rc == 1 and "NUL character" in err, err


def test_verify_of_a_manifest_that_is_a_list_is_a_clear_error(tmp_path, capsys):
    cache = tmp_path / "cache"
    cache.mkdir()
    bake_cache.manifest_path(cache).write_text("[1, 2, 3]")
    scene = tmp_path / "scene.json"
    scene.write_text(json.dumps(good_scene(cache)))
    rc, _, err = run(capsys, scene, "--verify")
    assert rc == 1 and "not a JSON object (it holds a list)" in err, err


def test_write_vdb_refuses_a_nul_in_the_path(tmp_path):
    path = str(tmp_path / "a.vdb") + "\u0000.tmp"
    with pytest.raises(hf.InvalidArgumentError, match="NUL character"):
        hf.write_vdb(path, np.zeros((8, 8, 8), dtype=np.float32), 0.1)
    assert not (tmp_path / "a.vdb").exists()
