# SPDX-License-Identifier: GPL-3.0-or-later
"""Refuse, at import, a numpy the native module cannot talk to.

pybind11 before 2.12 reads numpy's array structures as numpy 1 laid them out; under numpy 2 a
module built with it returns wrong values without an error (seen here: a source build with
Debian 12's pybind11 2.10 under numpy 2.4 gave every 3-vector its last component three times).
The wheels are built with pybind11 2.12 or newer; a source build takes the system's pybind11.
So the pairing is refused with what to do, rather than computing wrong forces.
"""

from __future__ import annotations

from typing import Sequence

NUMPY_2_PYBIND11 = (2, 12)  # the first pybind11 that supports numpy 2


def check_numpy(numpy_version: str, pybind11_version: Sequence[int]) -> None:
    """ImportError if a module built with ``pybind11_version`` would run under ``numpy_version``
    (numpy 2 with a pybind11 older than 2.12)."""
    major = int(numpy_version.split(".")[0])
    built = tuple(int(v) for v in pybind11_version)
    if major >= 2 and built < NUMPY_2_PYBIND11:
        raise ImportError(
            f"use a Python with numpy 1.x (e.g. Debian's /usr/bin/python3), or rebuild hapticfluid with pybind11 "
            f"{NUMPY_2_PYBIND11[0]}.{NUMPY_2_PYBIND11[1]} or newer (or install its wheel): this build's "
            f"pybind11 {built[0]}.{built[1]} cannot hand arrays to numpy {numpy_version} (they would come back "
            "wrong)")
