# SPDX-License-Identifier: GPL-3.0-or-later
"""Resume extends a finished bake when the end frame is raised (the checkpoint matches the
settings up to its own frame), and a change of settings is named and re-baked."""

import numpy as np
import pytest

from hapticfluid.bake import BakeError, bake, frame_path, list_frames, rebake_plan, scene_from_dict
from hapticfluid.bake.cache import load_checkpoint
from hapticfluid.bake.plan import InputsLedger
from hapticfluid.bake.openvdb_python import import_openvdb, missing_reason

vdb = import_openvdb()
if vdb is None:
    pytest.skip(missing_reason(), allow_module_level=True)


def per_frame_scene(cache, end, shift=0.0, **fluid):
    """Keys at every frame (as the Blender add-on samples them): raising end only adds keys."""
    return scene_from_dict({
        "domain": {"origin": [0.0, 0.0, 0.0], "size": [1.0, 1.0, 1.0]},
        "resolution": 12,
        "fluid": {"heat_buoyancy": 1.5, "vorticity": 0.3, "pressure_iterations": 8, **fluid},
        "source": {"centre": [0.5, 0.5, 0.25], "radius": 0.15, "temperature": 6.0},
        "probe": {"shape": "sphere", "radius": 0.12,
                  "keys": [{"frame": f, "location": [0.3 + shift + 0.05 * f, 0.5, 0.55]} for f in range(0, end + 1)]},
        "frames": {"start": 1, "end": end, "fps": 24},
        "substeps": 1,
        "cache": {"directory": str(cache), "grids": ["density"], "tolerance": 0.0},
    })


def density(cache, frame):
    grid = vdb.read(str(frame_path(cache, frame)), "density")
    out = np.zeros((12, 12, 12), dtype=np.float32)
    grid.copyToArray(out)
    return out


def test_raising_the_end_frame_and_resuming_extends_the_bake(tmp_path):
    reference = tmp_path / "ref"
    bake(per_frame_scene(reference, end=5))
    cache = tmp_path / "c"
    first = bake(per_frame_scene(cache, end=3))
    assert first.status == "finished" and list_frames(cache) == [1, 2, 3]
    extended = bake(per_frame_scene(cache, end=5), resume=True)
    assert extended.status == "finished" and extended.resumed_from == 3 and extended.frames_written == 2
    assert list_frames(cache) == [1, 2, 3, 4, 5]
    for frame in range(1, 6):  # as if baked to 5 in one go
        np.testing.assert_array_equal(density(reference, frame), density(cache, frame), err_msg=f"frame {frame}")


def test_resume_names_the_settings_that_changed_and_rebakes_what_they_change(tmp_path):
    """A changed global setting re-bakes every frame and names it; moved keys re-bake from the
    first frame they shape; a checkpoint loaded for other settings is refused naming them."""
    cache = tmp_path / "c"
    bake(per_frame_scene(cache, end=2))
    assert rebake_plan(per_frame_scene(cache, end=3, vorticity=0.9)).text == \
        "fluid.vorticity changed: re-bake every frame, 1-3"
    assert rebake_plan(per_frame_scene(cache, end=2).with_resolution(16)).text == \
        "grid_resolution, resolution changed: re-bake every frame, 1-2"
    assert rebake_plan(per_frame_scene(cache, end=2, shift=0.01)).text == \
        "probe keys changed from frame 1: re-bake 1-2 from the start"
    other = per_frame_scene(cache, end=2, vorticity=0.9)
    with pytest.raises(BakeError, match=r"\(fluid\.vorticity differ\)"):
        load_checkpoint(cache, other.fingerprint(), inputs_sha256=InputsLedger(other).chain)
    result = bake(per_frame_scene(cache, end=3, vorticity=0.9), resume=True)
    assert result.frames_written == 3 and result.plan.kind == "settings"
