// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/playback_guide.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"

namespace hf::haptics {

void GuideSettings::validate() const {
  const auto nonNegative = [](float v, const char* name, const char* unit) {
    if (!std::isfinite(v) || v < 0.0f) {
      throw InvalidArgument(std::string(name) + " must be a finite number of " + unit +
                            " >= 0 (0: from the device), got " + std::to_string(v));
    }
  };
  nonNegative(stiffness_n_m, "guide_stiffness", "N/m");
  nonNegative(damping_n_s_m, "guide_damping", "N s/m");
  nonNegative(max_force_n, "guide_max_force", "N");
  if (!std::isfinite(ramp_s) || ramp_s < 0.01 || ramp_s > 5.0) {
    throw InvalidArgument("guide_ramp must be between 0.01 and 5 s, got " + std::to_string(ramp_s));
  }
  if (!std::isfinite(stale_s) || stale_s < 0.05 || stale_s > 10.0) {
    throw InvalidArgument("guide_stale must be between 0.05 and 10 s, got " + std::to_string(stale_s));
  }
}

glm::vec3 carriedForward(const GuideTarget& target, double now_s, double stale_s) {
  const float ahead = static_cast<float>(std::clamp(now_s - target.time_s, 0.0, stale_s));
  return target.position_m + ahead * target.velocity_m_s;
}

PlaybackGuide::PlaybackGuide(const GuideSettings& s) : s_((s.validate(), s)) {}

void PlaybackGuide::reset() {
  weight_ = 0.0f;
  last_ = GuideTarget{};
}

GuideTick PlaybackGuide::step(const GuideTarget& target, const glm::vec3& hand_m, const glm::vec3& hand_m_s,
                              double now_s, double dt_s) {
  const double age_s = now_s - target.time_s;
  const bool usable = target.active && allFinite(target.position_m) && allFinite(target.velocity_m_s) &&
                      std::isfinite(age_s) && age_s <= s_.stale_s;
  if (usable) last_ = target;
  const float rate = static_cast<float>(dt_s / s_.ramp_s);
  weight_ = usable ? std::min(1.0f, weight_ + rate) : std::max(0.0f, weight_ - rate);
  GuideTick out;
  out.weight = weight_;
  if (weight_ <= 0.0f || !last_.active) return out;
  // Carried forward at its velocity: the host sets it at its own tick rate (30-60 Hz, less under load).
  out.target_m = carriedForward(last_, now_s, s_.stale_s);
  out.target_m_s = now_s - last_.time_s < s_.stale_s ? last_.velocity_m_s : glm::vec3(0.0f);
  if (!allFinite(hand_m) || !allFinite(hand_m_s)) return out;
  const glm::vec3 pull = s_.stiffness_n_m * (out.target_m - hand_m) + s_.damping_n_s_m * (out.target_m_s - hand_m_s);
  const float size = glm::length(pull);
  const glm::vec3 capped = size > s_.max_force_n && size > 0.0f ? pull * (s_.max_force_n / size) : pull;
  out.force_n = weight_ * capped;
  return out;
}

}  // namespace hf::haptics
