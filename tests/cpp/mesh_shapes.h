// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Closed triangle meshes for the mesh-probe tests (not a test itself: the CMake glob takes only
// *.cpp): box, tetrahedron, icosphere, and a CPU point-in-mesh reference (generalised winding
// number: the solid angle of the mesh seen from the point over 4 pi).
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "obstacle/triangle_mesh.h"

namespace hf::test {

inline obstacle::TriangleMesh boxMesh(const glm::vec3& lo, const glm::vec3& hi) {
  obstacle::TriangleMesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices_m.emplace_back((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
  }
  // Two counter-clockwise (seen from outside) triangles per face.
  const unsigned f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : f) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

inline obstacle::TriangleMesh tetraMesh(const std::array<glm::vec3, 4>& p) {
  obstacle::TriangleMesh m;
  m.vertices_m.assign(p.begin(), p.end());
  const unsigned f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& t : f) {
    glm::uvec3 tri(t[0], t[1], t[2]);
    const unsigned other = 6 - t[0] - t[1] - t[2];
    const glm::vec3 n = glm::cross(p[tri.y] - p[tri.x], p[tri.z] - p[tri.x]);
    if (glm::dot(n, p[other] - p[tri.x]) > 0.0f) std::swap(tri.y, tri.z);  // outward
    m.triangles.push_back(tri);
  }
  return m;
}

// Unit icosahedron subdivided `levels` times, projected onto the sphere of `radius` at `centre`.
inline obstacle::TriangleMesh icosphere(int levels, float radius, const glm::vec3& centre) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                               {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                               {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : v) p = glm::normalize(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto middle = [&](unsigned a, unsigned b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = static_cast<unsigned>(v.size() - 1);
    };
    std::vector<glm::uvec3> next;
    for (const auto& tri : f) {
      const unsigned a = middle(tri.x, tri.y), b = middle(tri.y, tri.z), c = middle(tri.z, tri.x);
      next.insert(next.end(), {{tri.x, a, c}, {tri.y, b, a}, {tri.z, c, b}, {a, b, c}});
    }
    f = std::move(next);
  }
  obstacle::TriangleMesh m;
  for (const auto& p : v) m.vertices_m.push_back(centre + radius * p);
  m.triangles = f;
  return m;
}

// Generalised winding number of the posed mesh around world point x (van Oosterom-Strackee).
inline double windingNumber(const obstacle::TriangleMesh& m, const glm::dmat4& transform, const glm::dvec3& x) {
  double total = 0.0;
  for (const auto& tri : m.triangles) {
    glm::dvec3 a = glm::dvec3(transform * glm::dvec4(glm::dvec3(m.vertices_m[tri.x]), 1.0)) - x;
    glm::dvec3 b = glm::dvec3(transform * glm::dvec4(glm::dvec3(m.vertices_m[tri.y]), 1.0)) - x;
    glm::dvec3 c = glm::dvec3(transform * glm::dvec4(glm::dvec3(m.vertices_m[tri.z]), 1.0)) - x;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    total += 2.0 * std::atan2(num, den);
  }
  return total / (4.0 * M_PI);
}

}  // namespace hf::test
