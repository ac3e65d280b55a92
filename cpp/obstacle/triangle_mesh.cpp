// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>

#include "common/error.h"
#include "common/format.h"

namespace hf::obstacle {
namespace {

struct PositionHash {
  std::size_t operator()(const glm::vec3& p) const {
    std::uint32_t b[3];
    std::memcpy(b, &p, sizeof b);
    return (static_cast<std::size_t>(b[0]) * 73856093u) ^ (static_cast<std::size_t>(b[1]) * 19349663u) ^
           (static_cast<std::size_t>(b[2]) * 83492791u);
  }
};

// Index of the first vertex at each bit-identical position (-0 and +0 merged).
std::vector<std::uint32_t> weld(const std::vector<glm::vec3>& v) {
  std::unordered_map<glm::vec3, std::uint32_t, PositionHash> first;
  first.reserve(v.size());
  std::vector<std::uint32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const glm::vec3 p = v[i] + glm::vec3(0.0f);  // -0 -> +0
    out[i] = first.emplace(p, static_cast<std::uint32_t>(i)).first->second;
  }
  return out;
}

}  // namespace

void validateMesh(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.vertices_m.size(), nt = mesh.triangles.size();
  if (nv == 0 || nt == 0) {
    throw InvalidArgument("the mesh is empty (" + std::to_string(nv) + " vertices, " + std::to_string(nt) +
                          " triangles); give at least one closed surface");
  }
  if (nv > kMaxMeshElements || nt > kMaxMeshElements) {
    throw InvalidArgument("the mesh has " + std::to_string(nv) + " vertices and " + std::to_string(nt) +
                          " triangles; at most " + std::to_string(kMaxMeshElements) +
                          " of each are supported: decimate it");
  }
  for (std::size_t i = 0; i < nv; ++i) {
    const glm::vec3& p = mesh.vertices_m[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw InvalidArgument("mesh vertex " + std::to_string(i) + " is not finite " + vecText(p) +
                            "; every vertex coordinate must be a finite number of metres");
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      if (tri[c] >= nv) {
        throw InvalidArgument("triangle " + std::to_string(t) + " uses vertex index " + std::to_string(tri[c]) +
                              " but the mesh has " + std::to_string(nv) + " vertices (indices 0.." +
                              std::to_string(nv - 1) + ")");
      }
    }
  }
  // Closed and consistently oriented: each undirected edge's uses in its two directions cancel.
  const std::vector<std::uint32_t> id = weld(mesh.vertices_m);
  std::unordered_map<std::uint64_t, int> balance;
  balance.reserve(nt * 3);
  for (const glm::uvec3& tri : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = id[tri[c]], b = id[tri[(c + 1) % 3]];
      if (a == b) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      balance[key] += a < b ? 1 : -1;
    }
  }
  std::size_t open = 0;
  std::uint64_t example = 0;
  for (const auto& [key, n] : balance) {
    if (n != 0) {
      if (open == 0 || key < example) example = key;
      ++open;
    }
  }
  if (open > 0) {
    const auto a = static_cast<std::uint32_t>(example >> 32), b = static_cast<std::uint32_t>(example & 0xffffffffu);
    throw MeshNotClosed("the mesh is not closed and consistently oriented: " + std::to_string(open) +
                          " edges (e.g. between vertices " + std::to_string(a) + " " + vecText(mesh.vertices_m[a]) +
                          " and " + std::to_string(b) + " " + vecText(mesh.vertices_m[b]) +
                          ") are not used once in each direction; close the holes and make the normals "
                          "consistent (in Blender: Mesh > Clean Up > Fill Holes, Normals > Recalculate Outside)");
  }
}

MeshExtent meshExtent(const TriangleMesh& mesh) {
  // Over the vertices that triangles use: loose vertices do not count.
  MeshExtent e;
  if (mesh.triangles.empty()) return e;
  e.lo = e.hi = mesh.vertices_m[mesh.triangles[0].x];
  for (const glm::uvec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      e.lo = glm::min(e.lo, mesh.vertices_m[t[c]]);
      e.hi = glm::max(e.hi, mesh.vertices_m[t[c]]);
    }
  }
  e.centre = 0.5f * (e.lo + e.hi);
  float r2 = 0.0f;
  for (const glm::uvec3& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) {
      const glm::vec3 d = mesh.vertices_m[t[c]] - e.centre;
      r2 = std::max(r2, glm::dot(d, d));
    }
  }
  e.radius = std::sqrt(r2) * (1.0f + 1e-6f);
  e.triangles = mesh.triangles.size();
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 a = mesh.vertices_m[t.x], b = mesh.vertices_m[t.y], c = mesh.vertices_m[t.z];
    const double d = glm::length(glm::max(a, glm::max(b, c)) - glm::min(a, glm::min(b, c)));
    e.triangle_size_sum += d;
    e.triangle_size_sq_sum += d * d;
  }
  return e;
}

void validateTransform(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!std::isfinite(m[c][r])) throw InvalidArgument("the transform must be finite; element [" +
                                                         std::to_string(r) + "][" + std::to_string(c) + "] is not");
    }
  }
  if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) {
    throw InvalidArgument("the transform must be affine (bottom row 0, 0, 0, 1), got (" + num(m[0][3]) + ", " +
                          num(m[1][3]) + ", " + num(m[2][3]) + ", " + num(m[3][3]) +
                          "); pass the object's matrix_world");
  }
  const glm::mat3 a(m);
  const float scale = std::max({glm::length(a[0]), glm::length(a[1]), glm::length(a[2])});
  if (!(std::fabs(glm::determinant(a)) > 1e-9f * scale * scale * scale)) {
    throw InvalidArgument("the transform is singular (it flattens the mesh to zero volume); give every axis a "
                          "nonzero scale");
  }
}

WorldBox worldBox(const MeshExtent& e, const glm::mat4& m) {
  WorldBox corners;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 local((i & 1) ? e.hi.x : e.lo.x, (i & 2) ? e.hi.y : e.lo.y, (i & 4) ? e.hi.z : e.lo.z);
    const glm::vec3 w(m * glm::vec4(local, 1.0f));
    corners.lo = i == 0 ? w : glm::min(corners.lo, w);
    corners.hi = i == 0 ? w : glm::max(corners.hi, w);
  }
  // The sphere's image is an ellipsoid; its half-extent along world axis a is r |row a of M|.
  const glm::vec3 c(m * glm::vec4(e.centre, 1.0f));
  glm::vec3 half;
  for (int a = 0; a < 3; ++a) half[a] = e.radius * glm::length(glm::vec3(m[0][a], m[1][a], m[2][a]));
  return {glm::max(corners.lo, c - half), glm::min(corners.hi, c + half)};
}

double columnVisitBound(const MeshExtent& e, const glm::mat4& m, float cell_size_m) {
  // A triangle of local box diagonal d spans at most s d / h columns per axis, s the largest
  // stretch of the transform (bounded by the Frobenius norm): sum (s d / h + 1)^2.
  const glm::mat3 a(m);
  const double s = std::sqrt(double(glm::dot(a[0], a[0])) + glm::dot(a[1], a[1]) + glm::dot(a[2], a[2]));
  const double k = s / cell_size_m;
  return k * k * e.triangle_size_sq_sum + 2.0 * k * e.triangle_size_sum + static_cast<double>(e.triangles);
}

}  // namespace hf::obstacle
