#include "haptics/passivity_controller.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"

namespace hf::haptics {

void PassivitySettings::validate() const {
  if (!std::isfinite(max_damping_n_s_m) || max_damping_n_s_m < 0.0f) {
    throw InvalidArgument("passivity_max_damping must be a finite number >= 0 N s/m (0: the device's maximum), got " +
                          std::to_string(max_damping_n_s_m));
  }
  if (!std::isfinite(velocity_deadband_m_s) || velocity_deadband_m_s < 0.0f) {
    throw InvalidArgument("passivity_deadband must be a finite number >= 0 m/s, got " +
                          std::to_string(velocity_deadband_m_s));
  }
  if (!std::isfinite(max_reserve_j) || max_reserve_j < 0.0) {
    throw InvalidArgument("passivity_reserve must be a finite number >= 0 J, got " + std::to_string(max_reserve_j));
  }
  if (!std::isfinite(reserve_decay_s) || reserve_decay_s <= 0.0) {
    throw InvalidArgument("passivity_memory must be a finite number > 0 s, got " + std::to_string(reserve_decay_s));
  }
}

PassivityController::PassivityController(const PassivitySettings& s) : s_(s) { s_.validate(); }

glm::vec3 PassivityController::apply(const glm::vec3& wanted_n, const glm::vec3& position_m,
                                     const glm::vec3& velocity_m_s, const glm::vec3& held_n, double dt_s) {
  st_.alpha_n_s_m = 0.0;
  st_.cut_n = 0.0;
  if (!allFinite(position_m) || !allFinite(held_n)) return wanted_n;  // nothing to observe this period
  const glm::dvec3 x(position_m);
  if (have_position_) {
    const double work_j = glm::dot(glm::dvec3(held_n), x - last_position_m_);
    st_.energy_j += work_j;
    st_.delivered_j += work_j;
  }
  last_position_m_ = x;
  have_position_ = true;
  const bool timed = std::isfinite(dt_s) && dt_s > 0.0;
  if (st_.energy_j < 0.0) {  // stored dissipation: forgotten over reserve_decay_s, never above the cap
    if (timed) st_.energy_j *= std::exp(-dt_s / s_.reserve_decay_s);
    st_.energy_j = std::max(st_.energy_j, -s_.max_reserve_j);
  }
  if (!s_.enabled || !timed || !allFinite(wanted_n) || !allFinite(velocity_m_s)) return wanted_n;
  const glm::dvec3 v(velocity_m_s);
  const double speed_sq = glm::dot(v, v);
  if (!(speed_sq > 0.0) || std::sqrt(speed_sq) < s_.velocity_deadband_m_s) return wanted_n;
  const glm::dvec3 wanted(wanted_n);
  const double excess_j = st_.energy_j + glm::dot(wanted, v) * dt_s;
  if (!(excess_j > 0.0) || !(s_.max_damping_n_s_m > 0.0f)) return wanted_n;
  // The bounded damper first ...
  const double alpha = std::min(excess_j / (speed_sq * dt_s), static_cast<double>(s_.max_damping_n_s_m));
  glm::dvec3 out = wanted - alpha * v;
  const double left_j = excess_j - alpha * speed_sq * dt_s;
  // ... then the push along the motion is cut back, to zero at most.
  double cut = 0.0;
  const double speed = std::sqrt(speed_sq);
  const glm::dvec3 along = v / speed;
  if (left_j > 0.0) {
    cut = std::clamp(left_j / (speed * dt_s), 0.0, std::max(0.0, glm::dot(out, along)));
    out -= cut * along;
  }
  st_.alpha_n_s_m = alpha;
  st_.cut_n = cut;
  st_.dissipated_j += (alpha * speed_sq + cut * speed) * dt_s;
  ++st_.active;
  return glm::vec3(out);
}

void PassivityController::reset() {
  const std::uint64_t resets = st_.resets + (have_position_ ? 1 : 0);  // repeated resets count once
  st_ = PassivityState{};
  st_.resets = resets;
  have_position_ = false;
}

}  // namespace hf::haptics
