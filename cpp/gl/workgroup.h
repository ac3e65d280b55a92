#pragma once
// Workgroup shape of every per-cell stage (8x8x4 = 256 invocations measured best for 3D
// textures on llvmpipe; reductions need a power of two) and the #defines that carry it.
#include <glm/glm.hpp>
#include <string>

#include "gl/compute_program.h"

namespace hf::gl {

inline constexpr glm::ivec3 kCellGroup{8, 8, 4};

inline Defines cellGroupDefines() {
  return {{"WG_X", std::to_string(kCellGroup.x)},
          {"WG_Y", std::to_string(kCellGroup.y)},
          {"WG_Z", std::to_string(kCellGroup.z)}};
}

// The same, for stages that end in writeGroupSum() (the first level of a reduction).
inline Defines groupSumDefines() {
  Defines d = cellGroupDefines();
  d.emplace_back("GROUP_SUM", "1");
  return d;
}

// Workgroup size of the one-dimensional stages (per vertex, per triangle): WG_LINEAR.
inline constexpr int kLinearGroup = 256;

inline Defines linearGroupDefines() { return {{"WG_LINEAR", std::to_string(kLinearGroup)}}; }

// Workgroups needed to cover `cells` with kCellGroup.
inline glm::ivec3 groupsFor(const glm::ivec3& cells) { return (cells + kCellGroup - 1) / kCellGroup; }

inline std::size_t groupCount(const glm::ivec3& cells) {
  const glm::ivec3 g = groupsFor(cells);
  return static_cast<std::size_t>(g.x) * g.y * g.z;
}

}  // namespace hf::gl
