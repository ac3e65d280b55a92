// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core: the private native module. Only calls the binding areas in order.
#include "python/bindings.h"

PYBIND11_MODULE(_core, m) {
  m.doc() = "Native engine of hapticfluid (private: import hapticfluid instead).";
  hf::python::addErrors(m);
  hf::python::addDevice(m);
  hf::python::addSettings(m);
  hf::python::addSimulation(m);
  hf::python::addHaptics(m);
  hf::python::addFalcon(m);
  hf::python::addIo(m);
  hf::python::addLog(m);
}
