// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/low_pass_filter.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"

namespace hf::haptics {

void LowPassSettings::validate() const {
  if (!std::isfinite(bandwidth_ratio) || bandwidth_ratio <= 0.0) {
    throw InvalidArgument("filter bandwidth_ratio (cutoff / simulation rate) must be > 0, got " +
                          std::to_string(bandwidth_ratio));
  }
  if (!std::isfinite(min_cutoff_hz) || !std::isfinite(max_cutoff_hz) || min_cutoff_hz <= 0.0 ||
      max_cutoff_hz < min_cutoff_hz) {
    throw InvalidArgument("filter cutoff range must satisfy 0 < min <= max (Hz), got " + std::to_string(min_cutoff_hz) +
                          " .. " + std::to_string(max_cutoff_hz));
  }
}

double cutoffForRate(const LowPassSettings& s, double sim_rate_hz) {
  if (!(sim_rate_hz > 0.0) || !std::isfinite(sim_rate_hz)) return s.min_cutoff_hz;
  return std::clamp(s.bandwidth_ratio * sim_rate_hz, s.min_cutoff_hz, s.max_cutoff_hz);
}

glm::vec3 LowPassFilter::update(const glm::vec3& x, double dt_s, double cutoff_hz) {
  constexpr double kTwoPi = 6.283185307179586;
  const double a = 1.0 - std::exp(-kTwoPi * cutoff_hz * dt_s);
  y_ += static_cast<float>(a) * (x - y_);
  return y_;
}

}  // namespace hf::haptics
