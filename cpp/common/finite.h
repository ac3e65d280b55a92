// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Finite-value tests shared by the layers that check host input and GPU results.
#include <cmath>
#include <glm/glm.hpp>

namespace hf {

inline bool allFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace hf
