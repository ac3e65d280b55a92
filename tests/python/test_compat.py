# SPDX-License-Identifier: GPL-3.0-or-later
"""A build whose pybind11 predates numpy 2 refuses to load under numpy 2 (it would return wrong
arrays), saying what to do; every other pairing loads."""

import numpy as np
import pytest

import hapticfluid as hf
from hapticfluid import _compat, _core


def test_numpy_2_with_an_old_pybind11_is_refused_with_the_fix():
    with pytest.raises(ImportError, match=r"^use a Python with numpy 1.x .* pybind11 2.10 cannot hand arrays to numpy 2.4.6"):
        _compat.check_numpy("2.4.6", (2, 10))


@pytest.mark.parametrize("numpy_version,pybind11", [("1.24.2", (2, 10)), ("1.26.4", (2, 13)), ("2.0.0", (2, 12)),
                                                    ("2.4.6", (3, 0))])
def test_every_other_pairing_loads(numpy_version, pybind11):
    _compat.check_numpy(numpy_version, pybind11)


def test_this_build_and_numpy_hand_3_vectors_back_intact():
    """The module records its pybind11; and here (a pairing it accepted) a 3-vector comes back
    with its three components, not the last one three times."""
    assert isinstance(_core._PYBIND11_VERSION, tuple) and len(_core._PYBIND11_VERSION) == 2
    _compat.check_numpy(np.__version__, _core._PYBIND11_VERSION)
    sim = hf.Simulation(hf.FluidSettings(resolution=(16, 16, 16)))
    try:
        sim.set_probe((0.5, 0.5, 0.5), 0.1, velocity=(0.4, 0.0, 0.0))
        force = sim.step(0.02).force
        assert force[0] < 0.0 and abs(force[1]) < 1e-3 * abs(force[0]) and force[2] > 0.0, force
    finally:
        sim.close()
