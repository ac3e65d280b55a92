// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// GripMotion: the grip's velocity as the passivity controller needs it, from the positions the
// loop reads: the mean velocity over the last kGripVelocitySpan periods, (x_n - x_{n-k}) / (t_n -
// t_{n-k}). Not the device's own velocity estimate: a driver may low-pass it (the Falcon's 15 ms
// time constant), and a damper on a velocity 15 ms late pushes instead of damping above ~17 Hz
// (phase lag > 90 degrees), which with a stiff hand fed a 25-30 Hz whirl that the controller
// then fed harder. This estimate lags by half the span (2 ms) and jitters by one encoder count
// over the span (0.04 mm / 4 ms = 10 mm/s on the Falcon) while the grip creeps; at rest it is 0.
// Spans tried at gain 1 on the simulated Falcon (20 runs each): 2 periods, too noisy (the
// controller chattered, 2.8 mm swings); 8, a 62 mJ window; 4 kept (ARCHITECTURE.md, passivity).
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

namespace hf::haptics {

inline constexpr std::size_t kGripVelocitySpan = 4;  // periods

class GripMotion {
 public:
  // One reading: position (m, device frame) and the period since the previous reading (s).
  // Returns the velocity (m/s): 0 until two readings, NaN for a non-finite reading (which
  // also restarts the estimate).
  glm::vec3 update(const glm::vec3& position_m, double dt_s);
  void reset() { count_ = 0; next_ = 0; }

 private:
  std::array<glm::dvec3, kGripVelocitySpan + 1> x_{};
  std::array<double, kGripVelocitySpan + 1> t_{};
  std::size_t count_ = 0;  // readings kept (at most kGripVelocitySpan + 1)
  std::size_t next_ = 0;   // slot of the next reading
  double now_s_ = 0.0;
};

}  // namespace hf::haptics
