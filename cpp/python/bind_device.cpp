// SPDX-License-Identifier: GPL-3.0-or-later
// Which device the engine would use, without making a simulation.
#include <pybind11/stl.h>

#include <array>

#include "gl/dispatch_floor.h"
#include "gl/egl_context.h"
#include "gl/gl_check.h"
#include "gl/gl_device.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/named_args.h"
#include "session/backend_choice.h"

namespace py = pybind11;

namespace hf::python {

void addDevice(py::module_& m) {
  m.def("list_egl_devices", [] { return gl::listDevices(); }, py::call_guard<py::gil_scoped_release>(),
        "One line per EGL device the engine can choose from: index, hardware or software.");
  py::tuple names(std::size(session::kBackendNames));
  for (std::size_t i = 0; i < std::size(session::kBackendNames); ++i) names[i] = session::kBackendNames[i];
  m.attr("BACKENDS") = names;  // the values FluidSettings.backend takes (besides '')
  defNamed(
      m, "probe_device",
      [](const std::string& request, const std::string& backend) {
        compute::DeviceInfo info;
        {
          py::gil_scoped_release release;
          info = session::startWorker(backend, request, 0, std::nullopt)->info();
        }
        return deviceDict(info);
      },
      py::arg("device") = "", py::arg("backend") = "",
      "Make the device a Simulation would use and describe it (backend 'gpu' or 'cpu', renderer,\n"
      "threads (CPU), vendor, version, platform, device_index, software (a GL renderer on the CPU),\n"
      "memory_bytes (free now), max_3d_texture_size, max_storage_block_bytes, warning).\n"
      "device: the EGL device: '' (HAPTICFLUID_EGL_DEVICE or auto: hardware first), 'hardware' (a GPU\n"
      "or an error), 'software' or an EGL device number. backend: 'auto', 'gpu', 'cpu' or ''\n"
      "(HAPTICFLUID_BACKEND or auto), as FluidSettings.backend.");
  m.def(
      "gl_counters",
      [] {
        const compute::DispatchCounters c = compute::dispatchCounters();
        py::dict d;
        d["dispatches"] = c.dispatches;
        d["invocations"] = c.invocations;
        d["syncs"] = c.syncs;
        return d;
      },
      "Compute dispatches, the shader invocations they launched (workgroups x local size) and\n"
      "GPU-to-CPU syncs (read-backs) since the process started, all simulations together:\n"
      "{'dispatches': int, 'invocations': int, 'syncs': int}.");
  defNamed(
      m, "measure_dispatch_floor",
      [](const std::array<int, 3>& resolution, int repeats, const std::string& device) {
        gl::DispatchFloor f;
        {
          py::gil_scoped_release release;
          gl::GlWorker worker(device);
          const glm::ivec3 cells(resolution[0], resolution[1], resolution[2]);
          f = worker.call([&] { return gl::measureDispatchFloor(cells, repeats); });
        }
        py::dict d;
        d["resolution"] = py::make_tuple(f.cells.x, f.cells.y, f.cells.z);
        d["repeats"] = f.repeats;
        d["launched"] = f.launched;
        d["empty_wall_ns"] = f.empty_wall_ns;
        d["empty_cpu_ns"] = f.empty_cpu_ns;
        d["store_wall_ns"] = f.store_wall_ns;
        d["store_cpu_ns"] = f.store_cpu_ns;
        return d;
      },
      py::arg("resolution"), py::arg("repeats") = 20, py::arg("device") = "",
      "Benchmarks only: what one launched compute invocation costs on a GL device before a stage\n"
      "does any work. Makes a context (device: as probe_device), then times `repeats` dispatches\n"
      "of one invocation per cell of `resolution` (nx, ny, nz cells), in the cell stages'\n"
      "workgroup shape: first with invocations that do nothing, then with each storing one\n"
      "float texel. Returns nanoseconds per launched invocation: {'empty_wall_ns',\n"
      "'empty_cpu_ns', 'store_wall_ns', 'store_cpu_ns'} (wall: until glFinish; cpu: this\n"
      "process's CPU time, llvmpipe's shader threads included), with 'resolution', 'repeats' and\n"
      "'launched' (invocations per dispatch). InvalidArgumentError for a cell count outside\n"
      "1..the device's 3D texture size or repeats < 1.");
}

}  // namespace hf::python
