// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core.write_vdb and vdb_info: argument conversion, docstrings, GIL release.
#include <pybind11/stl.h>

#include <string>

#include "common/error.h"
#include "io/vdb_writer.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/ensure_array.h"
#include "python/named_args.h"

namespace py = pybind11;

namespace hf::python {
namespace {

using FArray = py::array_t<float, py::array::f_style | py::array::forcecast>;

io::Compression parseCompression(const std::string& s) {
  if (s == "blosc") return io::Compression::Blosc;
  if (s == "zip") return io::Compression::Zip;
  if (s == "none") return io::Compression::None;
  throw InvalidArgument("compression must be 'blosc', 'zip' or 'none', got '" + s + "'");
}

// A 3D float array as an x-fastest view; `keep` holds the (possibly converted) copy alive.
io::DenseView denseView(const py::handle& obj, const char* what, std::vector<FArray>& keep) {
  py::array raw = ensureArray<py::array>(obj);
  if (!raw || raw.ndim() != 3) throw InvalidArgument(std::string(what) + " must be a 3D numpy array of floats");
  if (raw.dtype().kind() != 'f') {
    throw InvalidArgument(std::string(what) + " must hold floating-point values, got dtype " +
                          std::string(py::str(raw.dtype())));
  }
  FArray copy = ensureArray<FArray>(raw);  // MemoryError propagates
  if (!copy) throw InvalidArgument(std::string(what) + " cannot be converted to float32");
  keep.push_back(std::move(copy));
  const FArray& a = keep.back();
  io::DenseView v;
  v.data = a.data();
  v.shape = glm::ivec3(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), static_cast<int>(a.shape(2)));
  return v;
}

io::MetaValue metaValueUnchecked(const std::string& key, const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) return v.cast<std::int64_t>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::sequence>(v) && py::len(v) == 3) {
    py::sequence s = py::reinterpret_borrow<py::sequence>(v);
    bool ints = true;
    for (auto item : s) ints = ints && py::isinstance<py::int_>(item) && !py::isinstance<py::bool_>(item);
    if (ints) return glm::ivec3(s[0].cast<int>(), s[1].cast<int>(), s[2].cast<int>());
    return glm::vec3(s[0].cast<float>(), s[1].cast<float>(), s[2].cast<float>());
  }
  throw InvalidArgument("metadata '" + key + "' must be a bool, int, float, str or a 3-sequence of numbers, got " +
                        std::string(py::str(py::type::of(v).attr("__name__"))));
}

// pybind11 reports a failed conversion (an int beyond 64 bits, a vector item that is no
// number or beyond 32 bits) as a bare RuntimeError: name the entry and the limits instead.
io::MetaValue metaValue(const std::string& key, const py::handle& v) {
  try {
    return metaValueUnchecked(key, v);
  } catch (const py::cast_error&) {
    throw InvalidArgument("metadata '" + key + "' = " + std::string(py::repr(v)) +
                          " cannot be stored: ints must fit in 64 bits, 3-sequences hold numbers (ints within "
                          "32 bits)");
  }
}

}  // namespace

void addIo(py::module_& m) {
  defNamed(
      m, "write_vdb",
      [](const std::string& path, const py::handle& density, float voxel_size, const std::array<float, 3>& origin,
         const py::object& velocity, const py::object& pressure, const std::string& compression, bool half_float,
         float tolerance, const py::dict& metadata) {
        if (path.find('\0') != std::string::npos) {  // the file system would see it cut at the NUL
          throw InvalidArgument("path holds a NUL character (" + std::to_string(path.find('\0')) +
                                " bytes in); give the .vdb file's real path");
        }
        std::vector<FArray> keep;
        keep.reserve(5);
        io::VdbFrame frame;
        frame.density = denseView(density, "density", keep);
        frame.resolution = frame.density.shape;
        frame.voxel_size_m = voxel_size;
        frame.origin_m = toVec3(origin);
        if (!velocity.is_none()) {
          py::sequence uvw = py::reinterpret_borrow<py::sequence>(velocity);
          if (!py::isinstance<py::sequence>(velocity) || py::isinstance<py::str>(velocity) || py::len(uvw) != 3) {
            throw InvalidArgument("velocity must be a tuple (u, v, w) of face arrays, as Simulation.velocity() returns");
          }
          const char* names[3] = {"velocity u", "velocity v", "velocity w"};
          for (int a = 0; a < 3; ++a) frame.velocity[a] = denseView(uvw[a], names[a], keep);
        }
        if (!pressure.is_none()) frame.pressure = denseView(pressure, "pressure", keep);
        for (auto [k, v] : metadata) {
          const std::string key = py::str(k);
          frame.metadata.emplace_back(key, metaValue(key, v));
        }
        io::VdbWriteOptions options;
        options.compression = parseCompression(compression);
        options.half_float = half_float;
        options.tolerance = tolerance;
        py::gil_scoped_release release;
        io::writeVdbFrame(path, frame, options);
      },
      py::arg("path"), py::arg("density"), py::arg("voxel_size"), py::arg("origin") = std::array<float, 3>{0, 0, 0},
      py::arg("velocity") = py::none(), py::arg("pressure") = py::none(), py::arg("compression") = "blosc",
      py::arg("half_float") = false, py::arg("tolerance") = 0.0f, py::arg("metadata") = py::dict(),
      R"doc(
Write one frame as an OpenVDB file (atomically: a temporary file in the same folder, renamed
when complete; nothing appears at `path` if writing fails).

path: the .vdb file to write; its folder must exist and be writable.
density: float array (nx, ny, nz), smoke concentration at cell centres -> FloatGrid 'density'
    (class fog volume).
voxel_size: the cell edge h (m). origin: world position of the domain's minimum corner (m);
    cell (i, j, k)'s centre is origin + (i + 1/2, j + 1/2, k + 1/2) h.
velocity: optional (u, v, w) MAC face arrays (m/s) as Simulation.velocity() returns; written
    as Vec3SGrid 'velocity' at cell centres (mean of each cell's two faces; not staggered).
pressure: optional float array (nx, ny, nz), Pa -> FloatGrid 'pressure'.
compression: 'blosc', 'zip' or 'none' (see vdb_compressions()).
half_float: store the grids as 16-bit floats (about half the size; ~3 significant digits).
tolerance: values with |value| (|vector| for velocity) <= tolerance are left inactive (sparse).
metadata: name -> bool, int, float, str or a 3-sequence (ints -> vec3i, else vec3s); stored
    on the file and on every grid.
)doc");
  m.def("vdb_compressions", &io::supportedCompressions,
        "Compressions this OpenVDB build can write: a subset of ['none', 'zip', 'blosc'].");
  m.def("openvdb_version", &io::openvdbVersion, "Version of the OpenVDB library the module uses.");
}

}  // namespace hf::python
