// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Shared declarations of the binding files: each area adds itself to the module.
#include <pybind11/pybind11.h>

namespace hf::fluid {
struct FluidParams;
}

namespace hf::python {

template <class P>
class SettingTable;  // settings_class.h

void addErrors(pybind11::module_& m);
void addDevice(pybind11::module_& m);
void addSettings(pybind11::module_& m);  // before addSimulation and addHaptics: their enums and settings
void addSimulation(pybind11::module_& m);
void addHaptics(pybind11::module_& m);
void addFalcon(pybind11::module_& m);  // after addHaptics: reuses its Device type
void addIo(pybind11::module_& m);
void addLog(pybind11::module_& m);

// The fluid's settings, listed once (bind_settings.cpp): FluidSettings' fields and Simulation's
// properties.
const SettingTable<fluid::FluidParams>& fluidParamSettings();

// Delivers the engine's queued log messages to Python logging (GIL held; bind_log.cpp).
void flushLog();
// Flushes the log when it leaves scope, error or not (declare it before a gil_scoped_release:
// it then runs with the GIL held again). A failure to log never replaces the call's outcome.
struct FlushLogAfter {
  FlushLogAfter() = default;
  FlushLogAfter(const FlushLogAfter&) = delete;
  FlushLogAfter& operator=(const FlushLogAfter&) = delete;
  ~FlushLogAfter() {
    try {
      flushLog();
    } catch (...) {
    }
  }
};

}  // namespace hf::python
