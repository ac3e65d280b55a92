// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/grip_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/error.h"
#include "common/finite.h"

namespace hf::haptics {

namespace {
// The fit's slack for the readings' own rounding: float positions (device frame, within 0.1 m of
// the origin) are rounded to 7.5e-9 m at most, and a reading exactly at the resolution's edge must fit.
constexpr double kReadingRoundingM = 1e-8;
}  // namespace

GripMotion::GripMotion(double resolution_m) : resolution_m_(resolution_m) {
  if (!std::isfinite(resolution_m_) || resolution_m_ < 0.0) {
    throw InvalidArgument("grip motion: the position resolution must be a finite number of m >= 0, got " +
                          std::to_string(resolution_m_));
  }
}

glm::vec3 GripMotion::update(const glm::vec3& position_m, double dt_s) {
  if (!allFinite(position_m) || !std::isfinite(dt_s) || dt_s < 0.0) {
    reset();
    window_ = glm::uvec3(0u);
    return glm::vec3(std::numeric_limits<float>::quiet_NaN());
  }
  now_s_ = count_ == 0 ? 0.0 : now_s_ + dt_s;
  x_[next_] = glm::dvec3(position_m);
  t_[next_] = now_s_;
  next_ = (next_ + 1) % kSlots;
  if (count_ < kSlots) ++count_;
  window_ = glm::uvec3(0u);
  if (count_ < 2) return glm::vec3(0.0f);
  const std::size_t newest = slot(0);
  const std::size_t longest = resolution_m_ > 0.0 ? count_ - 1 : std::min(count_ - 1, kGripVelocitySpan);
  const std::size_t shortest = std::min(longest, kGripVelocitySpan);
  glm::dvec3 v(0.0);
  const double tolerance_m = resolution_m_ + kReadingRoundingM;
  for (int axis = 0; axis < 3; ++axis) {
    const double x0 = x_[newest][axis], t0 = t_[newest];
    // A reading i periods back lies within the tolerance of the line through the newest reading
    // with slope s when s is in [(x0 - x_i - tol) / dt_i, (x0 - x_i + tol) / dt_i]: the window grows
    // to n while the slope to the reading n back is in every such interval of the readings inside
    // (kept as their intersection, so each update is linear in the window).
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    const auto include = [&](std::size_t back) {
      const std::size_t s = slot(back);
      const double dt = t0 - t_[s];
      if (!(dt > 0.0)) {
        lo = std::numeric_limits<double>::infinity();  // no slope fits a reading at the same time
        return;
      }
      lo = std::max(lo, (x0 - x_[s][axis] - tolerance_m) / dt);
      hi = std::min(hi, (x0 - x_[s][axis] + tolerance_m) / dt);
    };
    std::size_t n = shortest;
    if (n < longest) {  // the window can grow (a resolution given): the readings inside the shortest
      for (std::size_t i = 1; i < n; ++i) include(i);
    }
    while (n < longest) {
      include(n);  // the readings inside the window n + 1
      const std::size_t far = slot(n + 1);
      const double span_s = t0 - t_[far];
      if (!(span_s > 0.0)) break;
      const double slope = (x0 - x_[far][axis]) / span_s;
      if (!(slope >= lo && slope <= hi)) break;
      ++n;
    }
    const std::size_t far = slot(n);
    const double span_s = t0 - t_[far];
    v[axis] = span_s > 0.0 ? (x0 - x_[far][axis]) / span_s : 0.0;
    window_[axis] = static_cast<unsigned>(n);
  }
  return glm::vec3(v);
}

}  // namespace hf::haptics
