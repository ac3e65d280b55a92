// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The seed paper's four cell classes (values shared with shaders/common.glsl).
#include <cstdint>

namespace hf::obstacle {

enum class CellClass : std::uint8_t {
  Outside = 0,      // fluid, no solid neighbour
  Surrounding = 1,  // fluid next to a boundary cell
  Boundary = 2,     // solid with at least one fluid neighbour
  Inside = 3,       // solid, every neighbour solid
};

}  // namespace hf::obstacle
