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

PassivityController::PassivityController(const PassivitySettings& s, float slew_rate_n_s)
    : s_(s), slew_rate_n_s_(slew_rate_n_s) {
  s_.validate();
  if (!std::isfinite(slew_rate_n_s_) || slew_rate_n_s_ < 0.0f) {
    throw InvalidArgument("passivity: slew_rate must be a finite number >= 0 N/s (0: none), got " +
                          std::to_string(slew_rate_n_s_));
  }
}

double PassivityController::unwindEnergy(double push_n, double speed_m_s) const {
  if (!(push_n > 0.0) || !(slew_rate_n_s_ > 0.0f)) return 0.0;
  return push_n * push_n * speed_m_s / (2.0 * kPlanSlewFraction * slew_rate_n_s_);
}

double PassivityController::allowedPush(double energy_j, double speed_m_s, double dt_s) const {
  // The largest push p along the motion with E + p |v| dt + unwind(p) <= 0.
  const double b = speed_m_s * dt_s;
  if (!(energy_j < 0.0)) return -energy_j / b;  // owed: a force against the motion pays it this period
  if (!(slew_rate_n_s_ > 0.0f)) return -energy_j / b;
  const double a = speed_m_s / (2.0 * kPlanSlewFraction * slew_rate_n_s_);
  return 2.0 * -energy_j / (b + std::sqrt(b * b - 4.0 * a * energy_j));  // the positive root, stably
}

glm::vec3 PassivityController::apply(const glm::vec3& wanted_n, const glm::vec3& position_m,
                                     const glm::vec3& velocity_m_s, const glm::vec3& held_n, double dt_s) {
  st_.alpha_n_s_m = 0.0;
  st_.cut_n = 0.0;
  acted_ = false;
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
  const double speed = std::sqrt(speed_sq);
  const glm::dvec3 along = v / speed;
  const glm::dvec3 wanted(wanted_n);
  const glm::dvec3 held(held_n);
  // What the device will hold this period if the wanted force passes: the slew-limited force.
  const double max_step_n = slew_rate_n_s_ > 0.0f ? slew_rate_n_s_ * dt_s : 0.0;
  glm::dvec3 delivered = wanted;
  if (max_step_n > 0.0 && glm::length(wanted - held) > max_step_n) {
    delivered = held + (wanted - held) * (max_step_n / glm::length(wanted - held));
  }
  const double push_n = glm::dot(delivered, along);
  const double excess_j = st_.energy_j + push_n * speed * dt_s + unwindEnergy(push_n, speed);
  if (!(excess_j > 0.0) || !(s_.max_damping_n_s_m > 0.0f)) return wanted_n;
  // The push along the motion must come down to what the budget allows (with no slew limit:
  // exactly the excess this period). The bounded damper first ...
  const double reduce_n = std::max(0.0, glm::dot(wanted, along) - allowedPush(st_.energy_j, speed, dt_s));
  const double alpha = std::min(reduce_n / speed, static_cast<double>(s_.max_damping_n_s_m));
  glm::dvec3 out = wanted - alpha * v;
  const double left_n = reduce_n - alpha * speed;
  // ... then the push along the motion is cut back, to zero at most.
  double cut = 0.0;
  if (left_n > 0.0) {
    cut = std::clamp(left_n, 0.0, std::max(0.0, glm::dot(out, along)));
    out -= cut * along;
  }
  // Through the slew limit the change along the motion goes first: a sideways change of the
  // wanted force must not use up the step that takes the push back.
  bool first = false;
  if (max_step_n > 0.0) {
    const glm::dvec3 change = out - held;
    if (glm::length(change) > max_step_n) {
      const double change_along = glm::dot(change, along);
      if (change_along < 0.0) {
        const double step_along = std::max(change_along, -max_step_n);
        glm::dvec3 sideways = change - change_along * along;
        const double room = std::sqrt(std::max(0.0, max_step_n * max_step_n - step_along * step_along));
        const double sideways_n = glm::length(sideways);
        if (sideways_n > room) sideways *= room / sideways_n;
        // A little inside the step, so the safety stage's float rounding leaves it as it is.
        out = held + (step_along * along + sideways) * (1.0 - 1e-6);
        first = true;
      }
    }
  }
  if (!(alpha > 0.0) && !(cut > 0.0) && !first) return wanted_n;
  st_.alpha_n_s_m = alpha;
  st_.cut_n = cut;
  st_.dissipated_j += (alpha * speed + cut) * speed * dt_s;
  ++st_.active;
  acted_ = true;
  return glm::vec3(out);
}

void PassivityController::reset() {
  const std::uint64_t resets = st_.resets + (have_position_ ? 1 : 0);  // repeated resets count once
  st_ = PassivityState{};
  st_.resets = resets;
  acted_ = false;
  have_position_ = false;
}

}  // namespace hf::haptics
