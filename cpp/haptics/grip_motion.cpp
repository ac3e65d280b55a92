// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/grip_motion.h"

#include <cmath>
#include <limits>

#include "common/finite.h"

namespace hf::haptics {

glm::vec3 GripMotion::update(const glm::vec3& position_m, double dt_s) {
  if (!allFinite(position_m) || !std::isfinite(dt_s) || dt_s < 0.0) {
    reset();
    return glm::vec3(std::numeric_limits<float>::quiet_NaN());
  }
  now_s_ = count_ == 0 ? 0.0 : now_s_ + dt_s;
  x_[next_] = glm::dvec3(position_m);
  t_[next_] = now_s_;
  const std::size_t newest = next_;
  next_ = (next_ + 1) % x_.size();
  if (count_ < x_.size()) ++count_;
  if (count_ < 2) return glm::vec3(0.0f);
  // The oldest reading kept: kGripVelocitySpan periods back once the ring is full.
  const std::size_t oldest = count_ < x_.size() ? 0 : next_;
  const double span_s = t_[newest] - t_[oldest];
  if (!(span_s > 0.0)) return glm::vec3(0.0f);
  return glm::vec3((x_[newest] - x_[oldest]) / span_s);
}

}  // namespace hf::haptics
