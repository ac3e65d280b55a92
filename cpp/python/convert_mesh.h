// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// numpy arrays -> the engine's mesh and pose types (shape and dtype checks only; the engine
// validates the values).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <string>

#include "common/error.h"
#include "obstacle/triangle_mesh.h"
#include "python/ensure_array.h"

namespace hf::python {

namespace py = pybind11;

inline std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// vertices (N, 3) real numbers (m) and triangles (M, 3) integers -> a mesh (copied).
inline obstacle::TriangleMesh toMesh(const py::array& vertices, const py::array& triangles) {
  const char vk = vertices.dtype().kind(), tk = triangles.dtype().kind();
  if (vertices.ndim() != 2 || vertices.shape(1) != 3 || (vk != 'f' && vk != 'i' && vk != 'u')) {
    throw InvalidArgument("vertices must be a real-number array of shape (N, 3) in metres, got shape " +
                          shapeText(vertices) + " of dtype " + std::string(py::str(vertices.dtype())));
  }
  if (triangles.ndim() != 2 || triangles.shape(1) != 3 || (tk != 'i' && tk != 'u')) {
    throw InvalidArgument("triangles must be an integer array of shape (M, 3) (vertex indices), got shape " +
                          shapeText(triangles) + " of dtype " + std::string(py::str(triangles.dtype())));
  }
  // Before any copy: a huge (or broadcast, zero-stride) array would otherwise be converted in
  // full only for validateMesh to refuse it.
  const auto nv = static_cast<std::size_t>(vertices.shape(0)), nt = static_cast<std::size_t>(triangles.shape(0));
  if (nv > obstacle::kMaxMeshElements || nt > obstacle::kMaxMeshElements) {
    throw InvalidArgument("the mesh has " + std::to_string(nv) + " vertices and " + std::to_string(nt) +
                          " triangles; at most " + std::to_string(obstacle::kMaxMeshElements) +
                          " of each are supported: decimate it");
  }
  // MemoryError (a copy that cannot be allocated) propagates; other failures give null arrays.
  const auto v = ensureArray<py::array_t<float, py::array::c_style | py::array::forcecast>>(vertices);
  const auto t = ensureArray<py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>>(triangles);
  if (!v || !t) throw InvalidArgument("vertices and triangles must be numeric arrays");
  obstacle::TriangleMesh mesh;
  const auto vr = v.unchecked<2>();
  mesh.vertices_m.resize(static_cast<std::size_t>(vr.shape(0)));
  for (py::ssize_t i = 0; i < vr.shape(0); ++i) mesh.vertices_m[i] = glm::vec3(vr(i, 0), vr(i, 1), vr(i, 2));
  const auto tr = t.unchecked<2>();
  mesh.triangles.resize(static_cast<std::size_t>(tr.shape(0)));
  for (py::ssize_t i = 0; i < tr.shape(0); ++i) {
    for (int c = 0; c < 3; ++c) {
      const std::int64_t index = tr(i, c);
      if (index < 0 || index > std::numeric_limits<std::uint32_t>::max()) {
        throw InvalidArgument("triangle " + std::to_string(i) + " has vertex index " + std::to_string(index) +
                              "; indices must be between 0 and the number of vertices - 1");
      }
      mesh.triangles[i][c] = static_cast<std::uint32_t>(index);
    }
  }
  return mesh;
}

// A 4x4 matrix (numpy array, nested sequences or Blender's matrix_world; row r, column c, the
// translation in the last column) -> glm (column-major). None -> identity.
inline glm::mat4 toTransform(const py::object& transform) {
  if (transform.is_none()) return glm::mat4(1.0f);
  const auto a = ensureArray<py::array_t<double, py::array::c_style | py::array::forcecast>>(transform);
  if (!a || a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4) {
    throw InvalidArgument("transform must be a 4x4 matrix (the object's matrix_world: rows of 4 numbers, "
                          "translation in the last column, metres) or None");
  }
  glm::mat4 m;
  const auto r = a.unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) m[col][row] = static_cast<float>(r(row, col));
  return m;
}

inline py::array_t<float> transformArray(const glm::mat4& m) {
  py::array_t<float> a({4, 4});
  auto w = a.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) w(row, col) = m[col][row];
  return a;
}

}  // namespace hf::python
