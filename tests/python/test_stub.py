# SPDX-License-Identifier: GPL-3.0-or-later
"""The shipped type stub names exactly what the native module offers."""

import ast
import inspect
from pathlib import Path

import hapticfluid


def stub_names():
    path = Path(hapticfluid.__file__).with_name("_core.pyi")
    tree = ast.parse(path.read_text())
    top, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            top.add(node.name)
            members[node.name] = {
                n.name if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) else n.target.id
                for n in node.body
                if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))
                or (isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name))
            }
        elif isinstance(node, ast.FunctionDef):
            top.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            top.add(node.target.id)
    return top, members


def public(names):
    """Names a user calls: no private ones; the context-manager dunders count."""
    return {n for n in names if not n.startswith("_") or n in ("__enter__", "__exit__")}


def test_stub_matches_module():
    top, members = stub_names()
    # The package re-exports the native module's whole API, so its __all__ is the reference.
    assert public(top) - {"Vec3"} == set(hapticfluid.__all__)
    for cls in ("Simulation", "StepReport"):
        real = {name for name, _ in inspect.getmembers(getattr(hapticfluid, cls))}
        assert public(members[cls]) == public(real), cls
