// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/drag_predictor.h"

#include <cmath>

#include "haptics/rendering/fit_slope.h"

namespace hf::haptics {

namespace {
// Velocity spread (m/s, rms) below which the slope is not fitted: the frames say nothing about B.
constexpr double kMinVelocitySpread = 1e-4;
}  // namespace

void DragPredictor::addFrame(const glm::vec3& force_n, const glm::vec3& velocity_m_s) {
  forces_[next_] = force_n;
  velocities_[next_] = velocity_m_s;
  next_ = (next_ + 1) % kWindow;
  if (count_ < kWindow) ++count_;
  f0_ = force_n;
  v0_ = velocity_m_s;
  fit();
}

void DragPredictor::fit() {
  if (count_ < 3) {
    b_ = glm::vec3(0.0f);
    return;
  }
  std::array<double, kWindow> v{}, f{};
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < count_; ++i) {
      v[i] = velocities_[i][a];
      f[i] = forces_[i][a];
    }
    const std::optional<double> b = fitSlope(v.data(), f.data(), count_, kMinVelocitySpread);
    b_[a] = (b && std::isfinite(*b) && *b < 0.0) ? static_cast<float>(*b) : 0.0f;
  }
}

glm::vec3 DragPredictor::predict(const glm::vec3& velocity_m_s) const {
  return f0_ + b_ * (velocity_m_s - v0_);
}

void DragPredictor::reset() {
  count_ = next_ = 0;
  f0_ = v0_ = b_ = glm::vec3(0.0f);
}

}  // namespace hf::haptics
