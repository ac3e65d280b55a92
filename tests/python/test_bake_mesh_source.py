# SPDX-License-Identifier: GPL-3.0-or-later
"""Bake with a mesh smoke source moved by keys (scene source.shape = "mesh"): the smoke lands
along the source's path and nowhere else, each frame adds rate x volume x frame time, and a
path that leaves the domain or an open mesh is refused before any frame is written."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import meshes
from hapticfluid.bake import bake, frame_path, scene_from_dict
from hapticfluid.bake.openvdb_python import import_openvdb, missing_reason

vdb = import_openvdb()
if vdb is None:
    pytest.skip(missing_reason(), allow_module_level=True)

RES = 24
SIZE = (0.6, 0.4, 0.4)  # m: 24 x 16 x 16 cells of 2.5 cm
H = 0.6 / RES
EDGE = 0.1  # m, the cube source
RATE = 2.0  # concentration per second
FPS = 24.0


def _scene(tmp_path, x_keys=((1, 0.1), (6, 0.45)), triangles=None, end=6, cache="cache", buoyancy=0.0):
    v, t = meshes.box((EDGE, EDGE, EDGE))
    return scene_from_dict({
        "domain": {"origin": [0, 0, 0], "size": list(SIZE)}, "resolution": RES,
        "fluid": {"gravity": [0, 0, 0], "pressure_iterations": 10, "heat_buoyancy": buoyancy},
        "source": {"shape": "mesh", "vertices": v.tolist(),
                   "triangles": (t if triangles is None else triangles).tolist(),
                   "keys": [{"frame": f, "location": [x, 0.2, 0.2]} for f, x in x_keys],
                   "density": RATE, "temperature": 1.0, "emission": "rate"},
        "frames": {"start": 1, "end": end, "fps": FPS}, "substeps": 2,
        "cache": {"directory": str(tmp_path / cache)}}, tmp_path)


def _density(path):
    grid = vdb.read(str(path), "density")
    out = np.zeros((RES, 16, 16), dtype=np.float32)
    grid.copyToArray(out, ijk=(0, 0, 0))
    return out


def test_animated_cube_source_leaves_smoke_along_its_path(tmp_path):
    scene = _scene(tmp_path)
    result = bake(scene)
    assert result.status == "finished" and result.frames_written == 6
    volume = EDGE ** 3
    for frame in (1, 6):
        d = _density(frame_path(scene.cache_dir, frame))
        emitted = d.sum(dtype=np.float64) * H ** 3
        seconds = frame / FPS
        # the cube's sampled volume is within one sub-column row of EDGE^3 at every pose
        row = EDGE * EDGE * H / hf.SOURCE_SUBSAMPLES
        assert abs(emitted - RATE * volume * seconds) <= RATE * row * seconds + 1e-6
    # frame 6: the cube went from x = 0.1 (frame 1's substeps start there) to 0.45
    per_x = d.sum(axis=(1, 2))
    lo, hi = 0.1 - EDGE / 2, 0.45 + EDGE / 2
    assert per_x[: int(lo / H)].sum() == 0.0 and per_x[int(np.ceil(hi / H)):].sum() == 0.0
    assert np.all(per_x[int(np.ceil(lo / H)):int(hi / H)] > 0.0)
    # and only in its y, z band
    per_y, per_z = d.sum(axis=(0, 2)), d.sum(axis=(0, 1))
    band = slice(int((0.2 - EDGE / 2) / H), int(np.ceil((0.2 + EDGE / 2) / H)))
    assert per_y.sum() == pytest.approx(per_y[band].sum()) and per_z.sum() == pytest.approx(per_z[band].sum())
    # each substep emits the same amount where the cube is when it ends (frame f - 1 + (s + 1) / 2),
    # so the smoke's centre of mass is the mean of those cube centres
    centres = [scene.source.trajectory.pose(f - 1 + (s + 1) / 2).translation[0] for f in range(1, 7) for s in range(2)]
    x = (np.arange(RES) + 0.5) * H
    assert (per_x * x).sum() / per_x.sum() == pytest.approx(np.mean(centres), abs=H / 8)


def test_resume_with_a_moving_source_gives_the_same_frames(tmp_path):
    """Stopped after frame 3 and extended to 6, the frames equal a bake in one go (the source's
    pose is a function of the substep's time; heat buoyancy makes the smoke move too)."""
    whole = _scene(tmp_path, cache="whole", buoyancy=3.0)
    assert bake(whole).status == "finished"
    part = _scene(tmp_path, cache="part", end=3, buoyancy=3.0)
    assert bake(part).status == "finished"
    extended = bake(_scene(tmp_path, cache="part", end=6, buoyancy=3.0), resume=True)
    assert extended.resumed_from == 3 and extended.frames_written == 3
    for frame in (4, 6):
        a, b = _density(frame_path(whole.cache_dir, frame)), _density(frame_path(part.cache_dir, frame))
        assert a.max() > 0.0 and np.array_equal(a, b), f"frame {frame}"


def test_a_source_path_leaving_the_domain_is_refused_before_baking(tmp_path):
    scene = _scene(tmp_path, x_keys=((1, 0.1), (6, 3.0)))
    with pytest.raises(hf.InvalidArgumentError, match=r"smoke source's path is refused at frame \d"):
        bake(scene)
    assert not frame_path(scene.cache_dir, 1).exists()


def test_an_open_source_mesh_is_refused_naming_the_mesh(tmp_path):
    _, t = meshes.box((EDGE, EDGE, EDGE))
    scene = _scene(tmp_path, triangles=t[:-1])
    with pytest.raises(hf.InvalidArgumentError, match="smoke source mesh: "):
        bake(scene)


def test_mesh_source_settings_are_in_the_fingerprint(tmp_path):
    a = _scene(tmp_path).fingerprint()["source"]
    b = _scene(tmp_path, x_keys=((1, 0.1), (6, 0.4))).fingerprint()["source"]
    assert a["shape"] == "mesh" and a["emission"] == "rate" and a["vertex_count"] == 8
    assert a["keys"] != b["keys"] and a["mesh_sha256"] == b["mesh_sha256"]
