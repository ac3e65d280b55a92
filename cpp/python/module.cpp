// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core: the private native module. Only calls the binding areas in order.
#include "python/bindings.h"

PYBIND11_MODULE(_core, m) {
  m.doc() = "Native engine of hapticfluid (private: import hapticfluid instead).";
  // The pybind11 this module was built with: one before 2.12 cannot hand arrays to numpy 2
  // (hapticfluid/_compat.py refuses that pairing at import).
  m.attr("_PYBIND11_VERSION") = pybind11::make_tuple(PYBIND11_VERSION_MAJOR, PYBIND11_VERSION_MINOR);
  hf::python::addErrors(m);
  hf::python::addDevice(m);
  hf::python::addSettings(m);
  hf::python::addSimulation(m);
  hf::python::addHaptics(m);
  hf::python::addFalcon(m);
  hf::python::addIo(m);
  hf::python::addLog(m);
}
