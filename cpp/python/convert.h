// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Conversions between engine types and Python objects (numpy arrays, tuples, dicts).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "gl/egl_context.h"

namespace hf::python {

namespace py = pybind11;

// A value given as a Python object, as T. A value of the wrong type raises TypeError naming the
// argument (pybind11's own "incompatible function arguments" names none).
template <class T>
T castArg(const py::handle& value, const char* name) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + ": wrong type " +
                         py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() + " (" +
                         py::repr(value).cast<std::string>() + ")");
  }
}

// A file path for the engine: a NUL character would cut it short, so it is refused, naming the argument.
inline const std::string& pathArg(const std::string& path, const char* name) {
  if (path.find('\0') != std::string::npos) {
    throw InvalidArgument(std::string(name) + " holds a NUL character; give a real file path");
  }
  return path;
}

inline glm::vec3 toVec3(const std::array<float, 3>& a) { return {a[0], a[1], a[2]}; }

inline py::array_t<float> vec3Array(const glm::vec3& v) {
  py::array_t<float> a(3);
  auto r = a.mutable_unchecked<1>();
  for (int i = 0; i < 3; ++i) r(i) = v[i];
  return a;
}

// A field read back x fastest becomes an array indexed [i, j, k] (Fortran-ordered, no copy).
template <class T>
py::array_t<T> fieldArray(std::vector<T>&& data, const glm::ivec3& shape) {
  auto* owned = new std::vector<T>(std::move(data));
  py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  const py::ssize_t s = static_cast<py::ssize_t>(sizeof(T));
  return py::array_t<T>({static_cast<py::ssize_t>(shape.x), static_cast<py::ssize_t>(shape.y),
                         static_cast<py::ssize_t>(shape.z)},
                        {s, s * shape.x, s * shape.x * shape.y}, owned->data(), owner);
}

inline py::dict deviceDict(const compute::DeviceInfo& info) {
  py::dict d;
  d["backend"] = compute::backendName(info.backend);
  d["threads"] = info.threads;
  d["renderer"] = info.renderer;
  d["vendor"] = info.vendor;
  d["version"] = info.version;
  d["egl_vendor"] = info.egl_vendor;
  d["platform"] = info.platform;
  d["device_index"] = info.device_index;
  d["software"] = info.software;
  d["memory_bytes"] = info.memory_bytes;
  d["max_3d_texture_size"] = info.max_3d_texture_size;
  d["max_storage_block_bytes"] = info.max_storage_block_bytes;
  d["warning"] = info.warning;
  return d;
}

}  // namespace hf::python
