// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// GripMotion: the grip's velocity from the positions the loop reads (the coupling's damper, the
// simulation's probe, the passivity controller and its dead-band: force_pipeline.h says which
// estimate each uses), by
// first-order adaptive windowing (end-fit FOAW, Janabi-Sharifi,
// Hayward and Chen 2000). Per axis, the velocity is the slope of the line through the newest
// reading and the one n periods back, n the longest window (kGripVelocitySpan <= n <=
// kGripVelocityMaxSpan) over which every reading in between lies within the device's position
// resolution of that line. A grip moving at a steady speed, or at rest, gets a long window and a
// quiet velocity; one that speeds up, stops or turns gets a short window and the velocity of now.
// Not the device's own velocity estimate: a driver may low-pass it (the Falcon's 15 ms time
// constant), and a damper on a velocity 15 ms late pushes instead of damping above ~17 Hz
// (phase lag > 90 degrees), which with a stiff hand fed a 25-30 Hz whirl that the controller then
// fed harder.
// Why adaptive: a fixed span of 4 periods (2 ms lag) jitters by one encoder count over the span
// (0.04 mm / 4 ms = 10 mm/s on the Falcon) while the grip creeps, and the Falcon's readings move on
// all three axes whenever any motor's count changes. A damper on that jitter, held for a period,
// delivers energy to the hand on every axis in the observer's books: on the simulated Falcon a slow
// push in water (12 mm/s) got 3.7 mJ on x and 4.9 mJ on y (the axis at rest) from the coupling's
// damper in 13 s, and the passivity controller damped the push at up to 20 N s/m for it (0.2 N
// where gain x the fluid's drag is 0.015 N). With the window the velocity is quiet within the
// resolution over the window (0.5 mm/s at 80 ms) and that energy falls about tenfold
// (docs/ARCHITECTURE.md, Force at the haptic rate). The window's cost: near a turn the readings fit
// a line within the resolution for up to ~7 ms, so a damper that must not push at the hand's turns
// (the passivity controller's) keeps the fixed span (GripMotion with no resolution). A device that
// reports no resolution (0: exact readings) keeps the fixed span. Spans tried at gain 1 on the
// simulated Falcon (20 runs each): 2 periods, too noisy (the controller chattered, 2.8 mm swings);
// 8, a 62 mJ window.
#include <array>
#include <cstddef>

#include <glm/glm.hpp>

namespace hf::haptics {

inline constexpr std::size_t kGripVelocitySpan = 4;      // the shortest window, periods
inline constexpr std::size_t kGripVelocityMaxSpan = 80;  // the longest window, periods

class GripMotion {
 public:
  // resolution_m: the spread of a position reading's quantization error per axis (m, >= 0;
  // DeviceInfo::position_resolution_m); 0: readings are exact and the window is kGripVelocitySpan.
  explicit GripMotion(double resolution_m = 0.0);
  // One reading: position (m, device frame) and the period since the previous reading (s).
  // Returns the velocity (m/s): 0 until two readings, NaN for a non-finite reading (which
  // also restarts the estimate).
  glm::vec3 update(const glm::vec3& position_m, double dt_s);
  void reset() { count_ = 0; next_ = 0; }
  // The window each axis used at the last update, periods (0 before two readings).
  const glm::uvec3& window() const { return window_; }

 private:
  static constexpr std::size_t kSlots = kGripVelocityMaxSpan + 1;
  // Slot of the reading `back` periods before the newest (back < count_).
  std::size_t slot(std::size_t back) const { return (next_ + kSlots - 1 - back) % kSlots; }

  double resolution_m_ = 0.0;
  std::array<glm::dvec3, kSlots> x_{};
  std::array<double, kSlots> t_{};
  std::size_t count_ = 0;  // readings kept (at most kSlots)
  std::size_t next_ = 0;   // slot of the next reading
  double now_s_ = 0.0;
  glm::uvec3 window_{0u};
};

}  // namespace hf::haptics
