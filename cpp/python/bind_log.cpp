// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core log: delivers the engine's queued messages (common/log_sink.h) to Python's
// logging, on the calling (host) thread with the GIL held. No logic beyond the hand-over.
#include <cstdint>
#include <string>
#include <vector>

#include "common/log_sink.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace hf::python {

void flushLog() {
  std::uint64_t dropped = 0;
  const std::vector<log::Message> messages = log::sink().drain(&dropped);
  if (messages.empty() && dropped == 0) return;
  const py::object get_logger = py::module_::import("logging").attr("getLogger");
  for (const log::Message& m : messages) {
    get_logger(m.logger).attr("log")(static_cast<int>(m.level), "%s", m.text);
  }
  if (dropped > 0) {
    get_logger("hapticfluid").attr("warning")(
        "%d engine log messages were dropped (more than %d queued between two flushes)", dropped,
        static_cast<int>(log::kLogCapacity));
  }
}

void addLog(py::module_& m) {
  static const std::string doc =
        "Deliver the engine's queued messages to Python logging (loggers 'hapticfluid.gl', "
        "'.fluid', '.haptics', '.session'). The engine's threads never take the GIL: they queue "
        "(at most " + std::to_string(log::kLogCapacity) + " messages, the rest counted and reported "
        "as dropped), and Simulation, HapticSession and the device calls flush after they return; "
        "call this to see a message from a running session's threads at once.";
  m.def("flush_log", &flushLog, doc.c_str());
}

}  // namespace hf::python
