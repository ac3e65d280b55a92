// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/force_safety.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"

namespace hf::haptics {

void SafetySettings::validate() const {
  if (!std::isfinite(max_force_n) || max_force_n <= 0.0f) {
    throw InvalidArgument("max_force must be a positive number of newtons, got " + std::to_string(max_force_n));
  }
  if (!std::isfinite(slew_rate_n_s) || slew_rate_n_s <= 0.0f) {
    throw InvalidArgument("slew_rate must be a positive number of N/s, got " + std::to_string(slew_rate_n_s));
  }
  if (static_cast<double>(max_force_n) / slew_rate_n_s > kMaxWindDownS) {
    throw InvalidArgument("slew_rate " + std::to_string(slew_rate_n_s) + " N/s would take " +
                          std::to_string(max_force_n / slew_rate_n_s) + " s to bring max_force " +
                          std::to_string(max_force_n) + " N down to zero on stop(); give at least " +
                          std::to_string(max_force_n / kMaxWindDownS) + " N/s (max_force / " +
                          std::to_string(kMaxWindDownS) + " s) or a lower max_force");
  }
  if (!std::isfinite(ramp_s) || ramp_s < 0.0) {
    throw InvalidArgument("ramp_time must be >= 0 s, got " + std::to_string(ramp_s));
  }
  if (!std::isfinite(stale_after_s) || stale_after_s <= 0.0 || stale_after_s > kMaxStaleS) {
    throw InvalidArgument("stale_after must be > 0 s and at most " + std::to_string(kMaxStaleS) +
                          " s (a larger value turns the fade of a stale force off), got " +
                          std::to_string(stale_after_s));
  }
  if (!std::isfinite(stale_periods) || stale_periods < 1.0 || stale_periods > kMaxStalePeriods) {
    throw InvalidArgument("stale_periods must be between 1 and " + std::to_string(kMaxStalePeriods) +
                          " simulation periods, got " + std::to_string(stale_periods));
  }
  if (!std::isfinite(stale_after_max_s) || stale_after_max_s <= 0.0 || stale_after_max_s > kMaxStaleS) {
    throw InvalidArgument("stale_after_max must be > 0 s and at most " + std::to_string(kMaxStaleS) +
                          " s (a stalled simulation's force must still fade), got " + std::to_string(stale_after_max_s));
  }
  if (!std::isfinite(fade_s) || fade_s <= 0.0 || fade_s > kMaxStaleS) {
    throw InvalidArgument("fade_time must be > 0 s and at most " + std::to_string(kMaxStaleS) + " s, got " +
                          std::to_string(fade_s));
  }
}

glm::vec3 clampMagnitude(const glm::vec3& v, float max_n) {
  const float len = glm::length(v);
  if (!(len > max_n)) return v;
  // A little inside the bound, so float rounding of the scaled vector never exceeds it.
  return v * (max_n * (1.0f - 1e-6f) / len);
}

glm::vec3 slewLimit(const glm::vec3& previous, const glm::vec3& target, float max_step_n) {
  return previous + clampMagnitude(target - previous, max_step_n);
}

double rampFactor(double since_start_s, double ramp_s) {
  if (ramp_s <= 0.0) return 1.0;
  return std::clamp(since_start_s / ramp_s, 0.0, 1.0);
}

double staleFactor(double age_s, double stale_after_s, double fade_s) {
  if (!(age_s > stale_after_s)) return 1.0;
  return std::clamp(1.0 - (age_s - stale_after_s) / fade_s, 0.0, 1.0);
}

double staleAfterS(const SafetySettings& s, double sim_rate_hz) {
  if (!(std::isfinite(sim_rate_hz) && sim_rate_hz > 0.0)) return s.stale_after_s;
  return std::clamp(s.stale_periods / sim_rate_hz, s.stale_after_s, std::max(s.stale_after_s, s.stale_after_max_s));
}

glm::vec3 ForceSafety::apply(const SafetyInput& in) {
  stale_after_s_ = staleAfterS(s_, in.sim_rate_hz);
  const float max_step_n =
      std::isfinite(in.dt_s) && in.dt_s > 0.0 ? s_.slew_rate_n_s * static_cast<float>(in.dt_s) : 0.0f;
  if (!in.homed) {  // the encoders are not zeroed: nothing, at once
    reset();
    return last_;
  }
  if (!in.enabled) {  // paused, stopping or failed: down to zero at the slew rate; the ramp restarts
    ramp_time_s_ = 0.0;
    last_ = max_step_n > 0.0f ? slewLimit(last_, glm::vec3(0.0f), max_step_n) : glm::vec3(0.0f);
    return last_;
  }
  if (!allFinite(in.force_n) || !std::isfinite(in.force_age_s)) {
    ++non_finite_;
    last_ = glm::vec3(0.0f);
    ramp_time_s_ = 0.0;
    return last_;
  }
  ramp_time_s_ += in.dt_s;
  const double scale = ramp() * staleFactor(in.force_age_s, stale_after_s_, s_.fade_s);
  const glm::vec3 target = clampMagnitude(static_cast<float>(scale) * in.force_n, s_.max_force_n);
  last_ = clampMagnitude(slewLimit(last_, target, max_step_n), s_.max_force_n);
  return last_;
}

void ForceSafety::reset() {
  last_ = glm::vec3(0.0f);
  ramp_time_s_ = 0.0;
}

}  // namespace hf::haptics
