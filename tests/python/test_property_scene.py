# SPDX-License-Identifier: GPL-3.0-or-later
"""Property-based tests (hypothesis) of the scene parser: any input either loads or raises the
documented error, InvalidArgumentError (a ValueError), never anything else (no KeyError,
TypeError, AttributeError, RecursionError, OverflowError...)."""

import json
import math

import pytest
from hypothesis import assume, HealthCheck, given, settings
from hypothesis import strategies as st

import hapticfluid as hf
from hapticfluid.bake.scene import BakeScene, load_scene, scene_from_dict

SETTINGS = settings(max_examples=100, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])

SCENE_KEYS = ["domain", "resolution", "fluid", "source", "probe", "frames", "substeps", "cfl", "max_substeps",
              "cache", "device", "origin", "size", "start", "end", "fps", "directory", "grids", "compression",
              "half_float", "tolerance", "keys", "frame", "location", "rotation", "scale", "matrix", "shape",
              "radius", "vertices", "triangles", "centre", "density", "temperature", "advection",
              "fluid_density", "gravity", "open_top", "pressure_solver", "pressure_iterations", "emission"]

scalars = (st.none() | st.booleans() | st.integers(-(1 << 70), 1 << 70)
           | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=8)
           | st.sampled_from(["sphere", "mesh", "adaptive", "blosc", "jacobi", "multigrid", "maccormack", "hold",
                              "rate"]))
json_values = st.recursive(
    scalars,
    lambda children: st.lists(children, max_size=5)
    | st.dictionaries(st.sampled_from(SCENE_KEYS) | st.text(max_size=5), children, max_size=6),
    max_leaves=30)


def valid_scene():
    return {"domain": {"origin": [0, 0, 0], "size": [1, 1, 1]}, "resolution": 16,
            "fluid": {"fluid_density": 1.2},
            "source": {"centre": [0.5, 0.5, 0.1], "radius": 0.1},
            "probe": {"shape": "sphere", "radius": 0.1,
                      "keys": [{"frame": 1, "location": [0.3, 0.5, 0.5]},
                               {"frame": 4, "location": [0.7, 0.5, 0.5], "rotation": [1, 0, 0, 0], "scale": 1.0}]},
            "frames": {"start": 1, "end": 4, "fps": 24}, "substeps": 2,
            "cache": {"directory": "cache", "grids": ["density"], "compression": "blosc"}}


def valid_mesh_source_scene():
    """The valid scene with an animated tetrahedron as the smoke source instead of the sphere."""
    data = valid_scene()
    data["source"] = {"shape": "mesh", "emission": "rate", "density": 2.0, "temperature": 1.0,
                      "vertices": [[0, 0, 0], [0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]],
                      "triangles": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                      "keys": [{"frame": 1, "location": [0.2, 0.4, 0.1]},
                               {"frame": 4, "matrix": [[1, 0, 0, 0.6], [0, 1, 0, 0.4], [0, 0, 1, 0.1], [0, 0, 0, 1]]}]}
    return data


def _paths(d, prefix=()):
    """Every (path) of keys/indices in a nested dict/list."""
    yield prefix
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _paths(v, prefix + (i,))


VALID_PATHS = [p for p in _paths(valid_scene()) if p]
MESH_SOURCE_PATHS = [p for p in _paths(valid_mesh_source_scene()["source"], ("source",))]


def _replace(d, path, value):
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value


def _parse(data, base):
    try:
        scene = scene_from_dict(data, base)
    except hf.InvalidArgumentError as exc:
        assert str(exc), "the error has no message"
        return None
    assert isinstance(scene, BakeScene)
    return scene


def test_the_valid_scene_loads(tmp_path):
    scene = _parse(valid_scene(), tmp_path)
    assert scene is not None and scene.frame_count == 4


# A changed value at every key of the scene, and what it changes of the fingerprint (None: nothing).
CHANGES = [
    (("domain", "origin"), [0.1, 0, 0], "domain_origin"), (("domain", "size"), [1.2, 1, 1], "domain_size"),
    (("resolution",), 20, "resolution"), (("frames", "start"), 2, "frame_start"), (("frames", "fps"), 30, "fps"),
    (("fluid", "vorticity"), 0.5, "fluid"), (("source", "radius"), 0.12, "source"),
    (("probe", "radius"), 0.11, "probe"),
    (("substeps",), 3, "substeps"), (("cfl",), 0.5, "cfl"), (("max_substeps",), 8, "max_substeps"),
    (("cache", "grids"), ["density", "pressure"], "grids"), (("cache", "compression"), "zip", "compression"),
    (("cache", "half_float"), True, "half_float"), (("cache", "tolerance"), 0.01, "tolerance"),
    (("frames", "end"), 5, None), (("cache", "directory"), "elsewhere", None), (("cache", "checkpoint_every"), 3, None),
    (("device",), "software", None),
]


@pytest.mark.parametrize("path, value, entry", CHANGES, ids=[".".join(map(str, c[0])) for c in CHANGES])
def test_one_list_says_what_outdates_a_cache(tmp_path, path, value, entry):
    """CACHE_INPUTS (what the add-on's "cache out of date" reads too) is what the fingerprint holds:
    a change at one of its keys changes that entry (grid_resolution derives from two of them), a
    change anywhere else changes nothing; cache_inputs() reads the same from the scene dict."""
    import copy

    from hapticfluid.bake.cache import settings_differences
    from hapticfluid.bake.scene import CACHE_INPUTS, cache_inputs

    assert {".".join(map(str, c[0][:1 if c[2] in ("fluid", "source", "probe") else 2])) for c in CHANGES
            if c[2]} == set(CACHE_INPUTS.values())
    before = valid_scene()
    after = copy.deepcopy(before)
    _replace(after, path, value)
    old, new = scene_from_dict(before, tmp_path).fingerprint(), scene_from_dict(after, tmp_path).fingerprint()
    assert set(new) == set(CACHE_INPUTS) | {"grid_resolution"}
    changed = {k for k in new if new[k] != old[k]} - {"grid_resolution"}
    assert changed == ({entry} if entry else set()), changed
    named = settings_differences(cache_inputs(before), cache_inputs(after))
    assert [n.split(".")[0] for n in named] == ([entry] if entry else []), named


@SETTINGS
@given(data=json_values)
def test_any_json_value_loads_or_is_refused(tmp_path, data):
    _parse(data, tmp_path)


# Each valid document: how to make it, the paths in it to change or remove, and the keys whose
# removal must be refused.
DOCUMENTS = {
    "probe scene": (valid_scene, VALID_PATHS,
                    (("domain",), ("resolution",), ("frames",), ("cache",), ("probe", "keys"))),
    "mesh source scene": (valid_mesh_source_scene, MESH_SOURCE_PATHS,
                          (("source", "keys"), ("source", "vertices"), ("source", "triangles"))),
}


@pytest.mark.parametrize("document", list(DOCUMENTS))
@SETTINGS
@given(data=st.data())
def test_one_changed_value_loads_or_is_refused(tmp_path, document, data):
    make, paths, _required = DOCUMENTS[document]
    doc = make()
    _replace(doc, data.draw(st.sampled_from(paths), label="path"), data.draw(json_values, label="value"))
    _parse(doc, tmp_path)


@pytest.mark.parametrize("document", list(DOCUMENTS))
@SETTINGS
@given(data=st.data())
def test_one_removed_key_loads_or_is_refused(tmp_path, document, data):
    make, paths, required = DOCUMENTS[document]
    path = data.draw(st.sampled_from([p for p in paths if isinstance(p[-1], str)]), label="path")
    doc = make()
    parent = doc
    for k in path[:-1]:
        parent = parent[k]
    del parent[path[-1]]
    scene = _parse(doc, tmp_path)
    if path in required:
        assert scene is None, f"removing required key {path} was accepted"


def test_the_valid_mesh_source_scene_loads(tmp_path):
    scene = _parse(valid_mesh_source_scene(), tmp_path)
    assert scene is not None and scene.source.shape == "mesh" and scene.source.emission == "rate"
    assert scene.source.trajectory.pose(2.5).translation[0] == pytest.approx(0.4)


@SETTINGS
@given(raw=st.binary(max_size=200) | json_values.map(lambda v: json.dumps(v).encode()))
def test_any_file_content_loads_or_is_refused(tmp_path, raw):
    p = tmp_path / "scene.json"
    p.write_bytes(raw)
    try:
        load_scene(p)
    except hf.InvalidArgumentError as exc:
        assert str(exc)


@SETTINGS
@given(fps=st.floats(min_value=1.0, max_value=240.0), end=st.integers(1, 50),
       resolution=st.integers(8, 64), size=st.tuples(*[st.floats(0.1, 3.0)] * 3))
def test_valid_numbers_give_a_consistent_scene(tmp_path, fps, end, resolution, size):
    data = valid_scene()
    data["frames"] = {"start": 1, "end": end, "fps": fps}
    data["resolution"] = resolution
    data["domain"]["size"] = list(size)
    data["probe"]["keys"] = [{"frame": 1, "location": [0.5 * s for s in size]}]
    data["probe"]["radius"] = 1.01 * max(size) / resolution  # just over one cell, as the engine asks
    data["source"]["centre"] = [0.5 * s for s in size]
    scene = _parse(data, tmp_path)
    # A refusal (e.g. the step range for this fps, with a message, as documented) is skipped with
    # assume(): hypothesis fails the test (Unsatisfiable / filter_too_much) when most are refused,
    # so a regression that refused every valid scene cannot pass here.
    assume(scene is not None)
    assert scene.frame_count == end
    assert scene.frame_dt == pytest.approx(1.0 / fps)
    assert max(scene.grid_resolution) == resolution
    assert all(n >= 8 for n in scene.grid_resolution)
    assert all(math.isfinite(h) for h in [scene.cell_size])
