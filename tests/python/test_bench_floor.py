# SPDX-License-Identifier: GPL-3.0-or-later
"""The dispatch-floor measurement counts what it launches exactly, refuses bad arguments by name,
and the ``floor`` benchmark section returns a well-formed table (its figures are not checked:
speed lives in benchmarks, not tests)."""

import json

import pytest

import hapticfluid as hf
from hapticfluid import _core
from hapticfluid.bench import floor, report


def test_dispatch_floor_counts_every_invocation_it_launches():
    repeats = 3
    before = _core.gl_counters()
    f = _core.measure_dispatch_floor((20, 16, 7), repeats, "software")
    after = _core.gl_counters()
    # The cell stages' 64 x 2 x 2 workgroups: x 20 -> 64, y 16 -> 16, z 7 -> 8 (padding counted).
    assert f["launched"] == 64 * 16 * 8
    assert f["resolution"] == (20, 16, 7) and f["repeats"] == repeats
    # Two programs (empty, store), each dispatched once untimed and `repeats` times timed.
    dispatches = 2 * (repeats + 1)
    assert after["dispatches"] - before["dispatches"] == dispatches
    assert after["invocations"] - before["invocations"] == dispatches * f["launched"]
    for key in ("empty_wall_ns", "empty_cpu_ns", "store_wall_ns", "store_cpu_ns"):
        assert f[key] >= 0.0
    assert f["empty_wall_ns"] > 0.0 and f["store_wall_ns"] > 0.0


@pytest.mark.parametrize("resolution, repeats, name", [
    ((0, 8, 8), 2, "resolution"),
    ((8, -1, 8), 2, "resolution"),
    ((8, 8, 100000), 2, "resolution"),
    ((8, 8, 8), 0, "repeats"),
])
def test_dispatch_floor_refuses_bad_arguments_by_name(resolution, repeats, name):
    with pytest.raises(hf.InvalidArgumentError, match=name):
        _core.measure_dispatch_floor(resolution, repeats, "software")


def test_a_step_launches_at_least_its_dispatches_over_the_grid():
    with hf.Simulation(resolution=(16, 16, 16), pressure_solver="multigrid", pressure_iterations=4) as sim:
        sim.step(1 / 60)
        before = _core.gl_counters()
        sim.step(1 / 60)
        after = _core.gl_counters()
    dispatches = after["dispatches"] - before["dispatches"]
    invocations = after["invocations"] - before["invocations"]
    assert dispatches > 0
    # Every dispatch launches at least one 256-invocation workgroup (the cell and linear stages'
    # size; the one-group reductions are at least 64), and the full-grid stages (advection,
    # divergence, the fine level's sweeps, projection) launch at least the grid each.
    assert invocations >= 64 * dispatches
    assert invocations >= 10 * 16 ** 3


def test_floor_section_is_well_formed(tmp_path):
    result = floor.run(quick=True, log=None)
    checked = report.check_section("floor", result)
    assert [row[0] for row in checked["rows"]] == ["bake scene (closed box)", "bench scene (open top)"]
    columns = result["columns"]
    for row in result["rows"]:
        assert len(row) == len(columns)
        values = dict(zip(columns, row))
        assert values["CG iterations/step"] >= 1
        assert values["M invocations/step"] * 1e6 >= values["dispatches/step"]
        cells = 1
        for n in values["grid"].split("x"):
            cells *= int(n)
        assert values["grid passes/step"] == pytest.approx(values["M invocations/step"] * 1e6 / cells)
        assert values["floor ms/step (store, wall)"] == pytest.approx(
            values["M invocations/step"] * 1e6 * values["store ns/inv (wall)"] * 1e-6)
    path = tmp_path / "floor.json"
    report.write_json_atomic(path, result)
    assert json.loads(path.read_text()) == result
