# SPDX-License-Identifier: GPL-3.0-or-later
"""OpenVDB's own Python bindings, whichever name they are installed under.

The package writes VDB files from C++ and never needs these bindings; tests and the Mantaflow
benchmark use them to read files back. OpenVDB up to 10 (Debian 12 and 13: python3-openvdb
10.0.1) names its module ``pyopenvdb``; OpenVDB 11 and newer (upstream's own builds, newer
distributions) name it ``openvdb``. The module is chosen by what imports, never by version.
"""

from __future__ import annotations

import importlib
from types import ModuleType
from typing import Optional

# Tried in this order; a module counts only if it has the grid types (a stray `openvdb` that
# is not OpenVDB's bindings is passed over).
MODULE_NAMES = ("pyopenvdb", "openvdb")


def import_openvdb() -> Optional[ModuleType]:
    """OpenVDB's Python module (``pyopenvdb`` or ``openvdb``), or None where neither imports."""
    for name in MODULE_NAMES:
        try:
            module = importlib.import_module(name)
        except ImportError:
            continue
        if hasattr(module, "FloatGrid") and hasattr(module, "read"):
            return module
    return None


def missing_reason() -> str:
    """Why :func:`import_openvdb` found nothing, with the fix (for skips and notes)."""
    return (f"OpenVDB's Python bindings are not importable (tried {', '.join(MODULE_NAMES)}): "
            "install python3-openvdb (Debian) or OpenVDB's Python module")
