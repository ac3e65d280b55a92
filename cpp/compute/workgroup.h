// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Workgroup shape of every per-cell stage and the #defines that carry it. 256 invocations (a
// power of two: reductions need one), long in x: with imageLoad/imageStore on llvmpipe, 64x2x2
// took 20-30% less CPU per step than 8x8x4 at 64^3 and 100x100x70 (bench scene, best of 8
// steps, under load; 128x2x1 was as good at 100 cells wide, worse where x is 64; 256x1x1 worse).
#include <glm/glm.hpp>
#include <string>

#include "compute/compute_program.h"

namespace hf::compute {

inline constexpr glm::ivec3 kCellGroup{64, 2, 2};

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

}  // namespace hf::compute
