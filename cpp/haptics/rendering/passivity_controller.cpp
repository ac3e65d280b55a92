// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/passivity_controller.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"

namespace hf::haptics {

void PassivitySettings::validate() const {
  if (max_damping_n_s_m && !(std::isfinite(*max_damping_n_s_m) && *max_damping_n_s_m > 0.0f)) {
    throw InvalidArgument("passivity_max_damping must be a finite number > 0 N s/m, or None (the device's maximum), got " +
                          std::to_string(*max_damping_n_s_m));
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

double PassivityController::unwindEnergy(double push_n, double speed_m_s, double accel_m_s2) const {
  if (!(push_n > 0.0) || !(slew_rate_n_s_ > 0.0f)) return 0.0;
  const double s = kPlanSlewFraction * slew_rate_n_s_;
  return push_n * push_n * speed_m_s / (2.0 * s) + std::max(0.0, accel_m_s2) * push_n * push_n * push_n / (6.0 * s * s);
}

double PassivityController::allowedPush(double energy_j, double speed_m_s, double accel_m_s2, double dt_s) const {
  // The largest push p along the motion with E + p |v| dt + unwind(p) <= 0.
  const double b = speed_m_s * dt_s;
  if (!(energy_j < 0.0)) return -energy_j / b;  // owed: a force against the motion pays it this period
  if (!(slew_rate_n_s_ > 0.0f)) return -energy_j / b;
  const double s = kPlanSlewFraction * slew_rate_n_s_;
  const double a = speed_m_s / (2.0 * s);
  double p = 2.0 * -energy_j / (b + std::sqrt(b * b - 4.0 * a * energy_j));  // the quadratic's positive root, stably
  if (!(accel_m_s2 > 0.0)) return p;
  // With the cubic term the root is smaller: Newton from the quadratic's root (above it; the
  // budget is convex and increasing in p, so the steps fall monotonically onto the root).
  for (int i = 0; i < 8; ++i) {
    const double g = energy_j + p * b + unwindEnergy(p, speed_m_s, accel_m_s2);
    const double slope = b + p * speed_m_s / s + accel_m_s2 * p * p / (2.0 * s * s);
    if (!(g > 0.0) || !(slope > 0.0)) break;
    p -= g / slope;
  }
  return std::max(0.0, p);
}

double PassivityController::allowedAgainst(double energy_j, double speed_m_s, double decel_m_s2) const {
  const double s = kPlanSlewFraction * slew_rate_n_s_;
  const double at_turn = std::cbrt(6.0 * s * s * std::max(0.0, kTurnAllowanceJ - energy_j) / decel_m_s2);
  return at_turn + s * speed_m_s / decel_m_s2;
}

void PassivityController::trackAcceleration(const glm::vec3& velocity_m_s, double dt_s) {
  if (!allFinite(velocity_m_s) || !(std::isfinite(dt_s) && dt_s > 0.0)) return;
  const glm::dvec3 v(velocity_m_s);
  if (have_velocity_) {
    const double k = dt_s / (kAccelFilterS + dt_s);
    accel_m_s2_ += k * ((v - last_velocity_m_s_) / dt_s - accel_m_s2_);
  }
  last_velocity_m_s_ = v;
  have_velocity_ = true;
}

glm::vec3 PassivityController::apply(const glm::vec3& wanted_n, const glm::vec3& position_m,
                                     const glm::vec3& velocity_m_s, const glm::vec3& held_n, double dt_s,
                                     double gate_speed_m_s) {
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
  trackAcceleration(velocity_m_s, dt_s);
  if (!s_.enabled || !timed || !allFinite(wanted_n) || !allFinite(velocity_m_s)) return wanted_n;
  const glm::dvec3 v(velocity_m_s);
  const double speed_sq = glm::dot(v, v);
  const double gate_m_s = gate_speed_m_s >= 0.0 ? gate_speed_m_s : std::sqrt(speed_sq);
  if (!(speed_sq > 0.0) || !(gate_m_s >= s_.velocity_deadband_m_s)) return wanted_n;
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
  if (!s_.max_damping_n_s_m) return wanted_n;  // observed only
  const double accel_along = glm::dot(accel_m_s2_, along);  // > 0: speeding up along the motion
  const double push_n = glm::dot(delivered, along);
  glm::dvec3 out = wanted;
  double alpha = 0.0, cut = 0.0, eased = 0.0;
  const double excess_j = st_.energy_j + push_n * speed * dt_s + unwindEnergy(push_n, speed, accel_along);
  if (excess_j > 0.0) {
    // The push along the motion must come down to what the budget allows (with no slew limit:
    // exactly the excess this period). The bounded damper first ...
    const double reduce_n = std::max(0.0, glm::dot(wanted, along) - allowedPush(st_.energy_j, speed, accel_along, dt_s));
    alpha = std::min(reduce_n / speed, static_cast<double>(*s_.max_damping_n_s_m));
    out = wanted - alpha * v;
    const double left_n = reduce_n - alpha * speed;
    // ... then the push along the motion is cut back, to zero at most.
    if (left_n > 0.0) {
      cut = std::clamp(left_n, 0.0, std::max(0.0, glm::dot(out, along)));
      out -= cut * along;
    }
  }
  if (slew_rate_n_s_ > 0.0f && accel_along < 0.0) {
    // Slowing down: the force against the motion is held to what can be unwound after the turn
    // (see the header), the damper's included.
    const double against_n = -glm::dot(out, along);
    const double limit_n = allowedAgainst(st_.energy_j, speed, -accel_along);
    if (against_n > limit_n) {
      eased = against_n - limit_n;
      out += eased * along;
    }
  }
  // The controller's change along the motion: < 0 takes a push back, > 0 eases a force against it.
  double change_along_sign = glm::dot(out - wanted, along);
  if (change_along_sign == 0.0 && excess_j > 0.0) change_along_sign = -1.0;  // the slewed push is the excess
  // Through the slew limit the change along the motion goes first: a sideways change of the
  // wanted force must not use up the step that takes the push back (or eases the force against
  // the motion before the turn).
  bool first = false;
  if (max_step_n > 0.0) {
    const glm::dvec3 change = out - held;
    if (glm::length(change) > max_step_n) {
      const double change_along = glm::dot(change, along);
      if (change_along * change_along_sign > 0.0) {
        const double step_along = std::clamp(change_along, -max_step_n, max_step_n);
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
  if (!(alpha > 0.0) && !(cut > 0.0) && !(eased > 0.0) && !first) return wanted_n;
  st_.alpha_n_s_m = alpha;
  st_.cut_n = cut;
  st_.dissipated_j += (alpha * speed + cut) * speed * dt_s;
  ++st_.active;
  if (eased > 0.0) ++st_.turn_ticks;
  acted_ = true;
  return glm::vec3(out);
}

void PassivityController::reset() {
  const std::uint64_t resets = st_.resets + (have_position_ ? 1 : 0);  // repeated resets count once
  st_ = PassivityState{};
  st_.resets = resets;
  acted_ = false;
  have_position_ = false;
  have_velocity_ = false;
  accel_m_s2_ = glm::dvec3(0.0);
}

}  // namespace hf::haptics
