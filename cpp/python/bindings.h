#pragma once
// Shared declarations of the binding files: each area adds itself to the module.
#include <pybind11/pybind11.h>

namespace hf::python {

void addErrors(pybind11::module_& m);
void addDevice(pybind11::module_& m);
void addSimulation(pybind11::module_& m);
void addHaptics(pybind11::module_& m);
void addFalcon(pybind11::module_& m);  // after addHaptics: reuses its Device type
void addIo(pybind11::module_& m);

}  // namespace hf::python
