// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Conversions between engine types and Python objects (numpy arrays, tuples, dicts).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
#include "gl/egl_context.h"

namespace hf::python {

namespace py = pybind11;

// What a value of T must be, in words: "a number", "3 numbers (x, y, z)", "a hapticfluid.Device".
template <class T>
std::string expected();

namespace detail {
template <class T>
struct Words {
  static std::string text() {
    if constexpr (std::is_same_v<T, bool>) {
      return "True or False";
    } else if constexpr (std::is_integral_v<T>) {
      return "an integer";
    } else if constexpr (std::is_floating_point_v<T>) {
      return "a number";
    } else if constexpr (std::is_same_v<T, std::string>) {
      return "a string";
    } else if constexpr (std::is_same_v<T, py::bytes>) {
      return "bytes";
    } else if constexpr (std::is_same_v<T, py::dict>) {
      return "a dict";
    } else if constexpr (std::is_same_v<T, py::array>) {
      return "a numpy array";
    } else if constexpr (std::is_base_of_v<py::array, T>) {
      return "an array of numbers";
    } else if constexpr (std::is_base_of_v<py::object, T>) {
      return "a " + std::string(py::detail::make_caster<T>::name.text);
    } else {  // a bound class
      return "a hapticfluid." + py::type::of<T>().attr("__name__").template cast<std::string>();
    }
  }
};
template <class T, std::size_t N>
struct Words<std::array<T, N>> {
  static std::string text() {
    const std::string n = std::to_string(N) + (std::is_integral_v<T> ? " integers" : " numbers");
    return N == 3 && !std::is_integral_v<T> ? n + " (x, y, z)" : n;
  }
};
template <class T>
struct Words<std::vector<T>> {
  static std::string text() {
    if constexpr (std::is_arithmetic_v<T>) return std::is_integral_v<T> ? "a list of integers" : "a list of numbers";
    return "a list of rows of " + expected<T>();
  }
};
template <class T>
struct Words<std::optional<T>> {
  static std::string text() { return expected<T>() + " or None"; }
};
template <class T>
struct Words<std::shared_ptr<T>> {
  static std::string text() { return expected<T>(); }
};
}  // namespace detail

template <class T>
std::string expected() {
  return detail::Words<py::detail::intrinsic_t<T>>::text();
}

// A value as a message shows it: its type and repr (cut at 60 characters), "str 'abc'".
inline std::string shown(const py::handle& value) {
  std::string text = py::repr(value).cast<std::string>();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>() + " " + text;
}

// "<name> must be <what T is>, got <the value>": the TypeError text for a value of the wrong type.
template <class T>
std::string wrongType(const py::handle& value, const std::string& name) {
  return name + " must be " + expected<T>() + ", got " + shown(value);
}

// A value given as a Python object, as T. A value of the wrong type raises TypeError naming the
// argument and what it must be.
template <class T>
T castArg(const py::handle& value, const char* name) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(wrongType<T>(value, name));
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
template <class T, class Alloc>
py::array_t<T> fieldArray(std::vector<T, Alloc>&& data, const glm::ivec3& shape) {
  using Vector = std::vector<T, Alloc>;
  auto* owned = new Vector(std::move(data));
  py::capsule owner(owned, [](void* p) { delete static_cast<Vector*>(p); });
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
