# SPDX-License-Identifier: GPL-3.0-or-later
"""The chooser of OpenVDB's Python module: `pyopenvdb` (OpenVDB <= 10) or `openvdb` (11+)."""

import sys
import types

import pytest

from hapticfluid.bake import openvdb_python


def test_neither_name_importable_gives_none_and_a_reason(monkeypatch):
    for name in openvdb_python.MODULE_NAMES:
        monkeypatch.setitem(sys.modules, name, None)  # None in sys.modules: import raises ImportError
    assert openvdb_python.import_openvdb() is None
    reason = openvdb_python.missing_reason()
    assert "pyopenvdb" in reason and "openvdb" in reason and "python3-openvdb" in reason


def test_the_newer_name_alone_is_found(monkeypatch):
    fake = types.ModuleType("openvdb")
    fake.FloatGrid, fake.read = object, lambda *a: None
    monkeypatch.setitem(sys.modules, "pyopenvdb", None)
    monkeypatch.setitem(sys.modules, "openvdb", fake)
    assert openvdb_python.import_openvdb() is fake


def test_a_stray_module_without_grid_types_is_passed_over(monkeypatch):
    monkeypatch.setitem(sys.modules, "pyopenvdb", None)
    monkeypatch.setitem(sys.modules, "openvdb", types.ModuleType("openvdb"))
    assert openvdb_python.import_openvdb() is None


def test_what_is_installed_here_reads_a_float_grid_back(tmp_path):
    vdb = openvdb_python.import_openvdb()
    if vdb is None:  # the installed bindings are what the bake tests read files with
        pytest.skip(openvdb_python.missing_reason())
    assert vdb.__name__ in openvdb_python.MODULE_NAMES
    grid = vdb.FloatGrid()
    grid.name = "density"
    grid.getAccessor().setValueOn((1, 2, 3), 0.5)
    vdb.write(str(tmp_path / "g.vdb"), grids=[grid])
    back = vdb.read(str(tmp_path / "g.vdb"), "density")
    assert back.getAccessor().getValue((1, 2, 3)) == 0.5 and back.activeVoxelCount() == 1
