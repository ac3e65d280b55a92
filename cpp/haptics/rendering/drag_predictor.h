// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// DragPredictor: inter-frame force prediction (beyond the seed). Between two simulation frames
// the probe keeps moving at 1 kHz; a local drag model F ~ F0 + B (v - v0) updates the force from
// the change of the probe's velocity since the frame (v0, F0) was computed. B (N s/m, one value
// per axis) is the least-squares slope of force against velocity over the recent frames. It is
// kept <= 0 (dissipative): a fitted B > 0 would feed energy into the user's hand, so it is 0.
#include <array>

#include <glm/glm.hpp>

namespace hf::haptics {

class DragPredictor {
 public:
  static constexpr int kWindow = 8;  // frames in the fit

  // One simulation frame: its force (N) and the probe velocity it was computed with (m/s).
  void addFrame(const glm::vec3& force_n, const glm::vec3& velocity_m_s);
  // F0 + B (v - v0) for the current probe velocity (m/s); F0 alone until B is known.
  glm::vec3 predict(const glm::vec3& velocity_m_s) const;
  const glm::vec3& dragNsM() const { return b_; }
  int frames() const { return count_; }
  void reset();

 private:
  void fit();

  std::array<glm::vec3, kWindow> forces_{};
  std::array<glm::vec3, kWindow> velocities_{};
  int count_ = 0;  // frames held (<= kWindow)
  int next_ = 0;   // ring index of the next frame
  glm::vec3 f0_{0.0f}, v0_{0.0f}, b_{0.0f};
};

}  // namespace hf::haptics
