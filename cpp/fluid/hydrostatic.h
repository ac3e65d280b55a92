// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The hydrostatic part of the pressure, rho g . (x - reference), which the solver leaves out
// (it solves the dynamic part only) and the force stage and pressure read-back add analytically.
#include <glm/glm.hpp>

#include "fluid/grid.h"

namespace hf::fluid {

// World point where the hydrostatic pressure is zero: the domain's highest point against gravity.
inline glm::vec3 hydrostaticReference(const Grid& g, const glm::vec3& gravity) {
  glm::vec3 ref = g.origin_m + 0.5f * g.sizeM();
  for (int a = 0; a < 3; ++a) {
    if (gravity[a] < 0.0f) ref[a] = g.origin_m[a] + g.sizeM()[a];
    if (gravity[a] > 0.0f) ref[a] = g.origin_m[a];
  }
  return ref;
}

}  // namespace hf::fluid
