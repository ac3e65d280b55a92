# SPDX-License-Identifier: GPL-3.0-or-later
"""The voxelize benchmark section runs and returns a well-formed, JSON-serialisable table
(on a tiny grid here; its figures are not checked: speed lives in benchmarks, not tests)."""

import json

import pytest

from hapticfluid.bench import voxelize


def test_voxelize_section_is_well_formed(tmp_path):
    result = voxelize.run(quick=True, grids=(16,))
    assert set(result) == {"title", "columns", "rows", "notes"}
    assert [row[2] for row in result["rows"]] == [0, 1000, 10000, 100000]
    for row in result["rows"]:
        assert len(row) == len(result["columns"])
        assert row[4] > 0.0 and row[5] > 0.0  # the GPU timer saw the stage run
    path = tmp_path / "voxelize.json"
    voxelize.write_json(result, str(path))
    assert json.loads(path.read_text()) == result
    assert [p.name for p in tmp_path.iterdir()] == ["voxelize.json"]  # no temporary left behind
    with pytest.raises(ValueError):  # NaN is not JSON: refused, and the earlier file stays whole
        voxelize.write_json({**result, "rows": [[float("nan")]]}, str(path))
    assert json.loads(path.read_text()) == result
