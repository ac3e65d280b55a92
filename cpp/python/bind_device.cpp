// Which GL device the engine would use, without making a simulation.
#include <pybind11/stl.h>

#include "gl/egl_context.h"
#include "gl/gl_check.h"
#include "gl/gl_worker.h"
#include "python/bindings.h"
#include "python/convert.h"

namespace py = pybind11;

namespace hf::python {

void addDevice(py::module_& m) {
  m.def("list_egl_devices", [] { return gl::listDevices(); }, py::call_guard<py::gil_scoped_release>(),
        "One line per EGL device the engine can choose from: index, hardware or software.");
  m.def(
      "probe_device",
      [](const std::string& request) {
        gl::ContextInfo info;
        {
          py::gil_scoped_release release;
          gl::GlWorker worker(request);
          info = worker.info();
        }
        return deviceDict(info);
      },
      py::arg("device") = "",
      "Make a GL context as a Simulation would and describe it (renderer, vendor, version,\n"
      "platform, device_index, software, memory_bytes (free now), max_3d_texture_size,\n"
      "max_storage_block_bytes, warning).\n"
      "device: '' (HAPTICFLUID_EGL_DEVICE or auto: hardware first), 'hardware' (a GPU or an error),\n"
      "'software' or an EGL device number.");
  m.def(
      "gl_counters",
      [] {
        const gl::GlCounters c = gl::glCounters();
        py::dict d;
        d["dispatches"] = c.dispatches;
        d["syncs"] = c.syncs;
        return d;
      },
      "Compute dispatches and GPU-to-CPU syncs (read-backs) since the process started, all\n"
      "simulations together: {'dispatches': int, 'syncs': int}.");
}

}  // namespace hf::python
