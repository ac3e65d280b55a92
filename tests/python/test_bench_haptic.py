# SPDX-License-Identifier: GPL-3.0-or-later
"""The haptic benchmark section runs in quick mode and returns a well-formed table."""

import json

from hapticfluid.bench import haptic


def test_quick_run_gives_a_table(tmp_path):
    out = tmp_path / "haptic.json"
    assert haptic.main(["--quick", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert set(doc) == {"schema", "quick", "machine", "sections"} and doc["quick"] is True
    result = doc["sections"]["haptic"]
    assert set(result) == {"title", "columns", "rows", "notes"}
    assert result["columns"] == haptic.COLUMNS
    assert len(result["rows"]) == 4 + len(haptic.QUICK_CONVERGED_GRIDS)
    col = {name: i for i, name in enumerate(result["columns"])}
    for row in result["rows"]:
        assert len(row) == len(result["columns"])
        # the loop ran (its rate is a benchmark figure: the rules keep timings out of tests)
        assert row[col["loop rate (Hz)"]] > 0.0
        assert 0.0 <= row[col["jitter p50 (ms)"]] <= row[col["jitter p99 (ms)"]] <= row[col["jitter max (ms)"]]
    busy = [r for r in result["rows"] if r[col["scenario"]] == "simulation running"]
    assert len(busy) == 2 and all(r[col["sim rate (Hz)"]] > 0.0 for r in busy)
    assert any(r[col["latency p50 (ms)"]] is not None for r in busy)
    converged = [r for r in result["rows"] if r[col["scenario"]].startswith("converged solver")]
    assert [r[col["grid"]] for r in converged] == [f"{n}^3" for n in haptic.QUICK_CONVERGED_GRIDS]
    assert all(r[col["sim rate (Hz)"]] > 0.0 for r in converged)
    assert [p.name for p in tmp_path.iterdir()] == ["haptic.json"]  # nothing else, no temporary
