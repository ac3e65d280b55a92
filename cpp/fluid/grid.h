// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The simulation grid: cubic cells over an axis-aligned box in world space (metres, z up).
#include <cstddef>
#include <glm/glm.hpp>

namespace hf::fluid {

struct Grid {
  glm::ivec3 res{64, 64, 64};        // cells per axis
  float cell_size_m = 1.0f / 64.0f;  // edge of one cubic cell, m
  glm::vec3 origin_m{0.0f};          // world position of the domain's minimum corner, m

  std::size_t cells() const { return static_cast<std::size_t>(res.x) * res.y * res.z; }
  glm::vec3 sizeM() const { return glm::vec3(res) * cell_size_m; }
  // World metres <-> grid units (cell i spans [i, i+1]).
  glm::vec3 toGrid(const glm::vec3& world_m) const { return (world_m - origin_m) / cell_size_m; }
  glm::vec3 toWorld(const glm::vec3& grid) const { return origin_m + grid * cell_size_m; }
  // Texels of the staggered velocity component on `axis`'s faces: one more along that axis.
  glm::ivec3 faceSize(int axis) const {
    glm::ivec3 s = res;
    s[axis] += 1;
    return s;
  }
  // Grid-unit position of that component's texel (0,0,0): the centre of cell 0's low face.
  static glm::vec3 faceOffset(int axis) {
    glm::vec3 o(0.5f);
    o[axis] = 0.0f;
    return o;
  }
};

}  // namespace hf::fluid
