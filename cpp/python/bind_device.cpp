// Which GL device the engine would use, without making a simulation.
#include <pybind11/stl.h>

#include "gl/egl_context.h"
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
      "platform, device_index, software, memory_bytes, max_3d_texture_size).\n"
      "device: '' (HAPTICFLUID_EGL_DEVICE or auto: hardware first), 'software' or an EGL device number.");
}

}  // namespace hf::python
