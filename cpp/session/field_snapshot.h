// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// FieldSnapshot: the fields a HapticSession's simulation thread read back right after one of
// its steps, published whole (immutable once made) so the host can draw the newest one without
// ever waiting for the GPU. Arrays are cell-centred, x fastest: index = i + nx * (j + ny * k).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace hf::session {

struct FieldSnapshot {
  std::uint64_t sequence = 0;        // 1 for the session's first snapshot, +1 for each later one
  glm::ivec3 resolution{0};          // cells per axis
  double time_s = 0.0;               // simulation time after the step, s
  std::int64_t steps = 0;            // the simulation's step count after the step
  std::vector<float> density;        // smoke concentration (dimensionless)
  std::vector<float> temperature;    // K above ambient; empty unless the session was asked for it
};

}  // namespace hf::session
