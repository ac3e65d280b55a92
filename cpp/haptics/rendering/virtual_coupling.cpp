// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/virtual_coupling.h"

#include <cmath>

#include "common/error.h"

namespace hf::haptics {

void CouplingSettings::validate() const {
  if (!std::isfinite(stiffness_n_m) || stiffness_n_m < 0.0f) {
    throw InvalidArgument("coupling_stiffness must be a finite number of N/m >= 0 (0: from the device), got " +
                          std::to_string(stiffness_n_m));
  }
  if (!std::isfinite(damping_n_s_m) || damping_n_s_m < 0.0f) {
    throw InvalidArgument("coupling_damping must be a finite number of N s/m >= 0 (0: from the device), got " +
                          std::to_string(damping_n_s_m));
  }
  if (!std::isfinite(added_mass_kg) || added_mass_kg < 0.0) {
    throw InvalidArgument("the probe's added mass must be a finite number of kg >= 0, got " + std::to_string(added_mass_kg));
  }
}

void VirtualCoupling::place(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& external_n) {
  x_ = glm::dvec3(hand_m) + (k_ > 0.0 ? glm::dvec3(external_n) / k_ : glm::dvec3(0.0));
  v_ = glm::dvec3(hand_m_s);
  a_ = glm::dvec3(0.0);
  mass_kg_ = glm::dvec3(-1.0);
  placed_ = true;
}

void VirtualCoupling::yieldTo(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& delivered_n) {
  if (!placed_ || !(k_ > 0.0)) return;
  for (int i = 0; i < 3; ++i) {
    // The hand feels -(k (xh - x) + b (vh - v)); the stretch that gives it `delivered`:
    const double stretch = hand_m[i] - x_[i];
    const double wanted = -(delivered_n[i] + b_ * (hand_m_s[i] - v_[i])) / k_;
    if (std::isfinite(wanted) && std::fabs(wanted) < std::fabs(stretch)) x_[i] = hand_m[i] - wanted;
  }
}

glm::vec3 VirtualCoupling::step(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& mass_kg,
                                const glm::vec3& drag_n_s_m, const glm::vec3& external_n, double dt_s) {
  const glm::dvec3 xh(hand_m), vh(hand_m_s);
  if (!placed_) {
    x_ = xh;
    v_ = a_ = glm::dvec3(0.0);
    mass_kg_ = glm::dvec3(-1.0);
    placed_ = true;
  }
  glm::dvec3 force(0.0);
  for (int i = 0; i < 3; ++i) {
    const double m = mass_kg[i], d = drag_n_s_m[i];
    if (m > mass_kg_[i] && mass_kg_[i] >= 0.0) v_[i] *= mass_kg_[i] / m;  // momentum kept: no energy added
    mass_kg_[i] = m;
    // m (v' - v) / dt = f_ext - d v' + k (xh - x - dt v') + b (vh - v')
    const double denom = m / dt_s + d + b_ + k_ * dt_s;
    const double v_new = (m * v_[i] / dt_s + external_n[i] + k_ * (xh[i] - x_[i]) + b_ * vh[i]) / denom;
    a_[i] = (v_new - v_[i]) / dt_s;
    v_[i] = v_new;
    x_[i] += dt_s * v_new;
    force[i] = -(k_ * (xh[i] - x_[i]) + b_ * (vh[i] - v_[i]));
  }
  return glm::vec3(force);
}

}  // namespace hf::haptics
