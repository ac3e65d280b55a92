// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Reductions by rows: a stage runs one invocation per row of cells along x, loops over the row
// and writes the row's vec4 sum to partials[j + ny * k]; GroupReducer sums those. It needs no
// workgroup barriers, which llvmpipe runs slowly: a shared-memory tree (GROUP_SUM) cost about
// seven Jacobi sweeps per reduced stage at 64^3, a row loop costs about one.
#include <cstddef>
#include <glm/glm.hpp>
#include <string>

#include "compute/compute_program.h"

namespace hf::fluid {

inline constexpr glm::ivec2 kRowGroup{8, 8};

inline compute::Defines rowGroupDefines() {
  return {{"ROW_X", std::to_string(kRowGroup.x)}, {"ROW_Y", std::to_string(kRowGroup.y)}};
}

// The invocations a row stage dispatches, and the partials it writes.
inline glm::ivec3 rowInvocations(const glm::ivec3& res) { return {res.y, res.z, 1}; }
inline std::size_t rowCount(const glm::ivec3& res) { return static_cast<std::size_t>(res.y) * res.z; }

}  // namespace hf::fluid
