# SPDX-License-Identifier: GPL-3.0-or-later
"""The pressure benchmark section runs (quick: small grids) and returns a well-formed,
JSON-serialisable table whose rows say what each solver did (iterations, residuals); its
times are not checked: speed lives in benchmarks, not tests."""

import json

from hapticfluid.bench import pressure


def test_pressure_benchmark_quick():
    result = pressure.run(quick=True)
    json.dumps(result)
    assert set(result) == {"title", "columns", "rows", "notes"}
    assert result["columns"][:3] == ["grid", "solver", "iterations"]
    assert all(len(row) == len(result["columns"]) for row in result["rows"])
    rows = [dict(zip(result["columns"], row)) for row in result["rows"]]
    assert {r["solver"] for r in rows} == {"jacobi", "multigrid"}
    for grid in {r["grid"] for r in rows}:
        jacobi, multigrid = (next(r for r in rows if r["grid"] == grid and r["solver"] == s)
                             for s in ("jacobi", "multigrid"))
        assert multigrid["reached_residual"] <= pressure.TOLERANCE * 1.5, multigrid
        assert multigrid["iterations"] < 20 < jacobi["iterations"], (jacobi, multigrid)
        assert multigrid["convergence_factor"] < 0.5 < jacobi["convergence_factor"], (jacobi, multigrid)
