// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// FluidModel: the local model of the fluid's force on the probe (the intermediate representation
// of Adachi et al. 1995 and Mark et al. 1996), identified from every simulation step and evaluated
// at the haptic rate against the probe's own motion (fluid frame, SI):
//   F(v, a) = F_s + B v - m_a a
//   m_a  the probe's added mass (kg): identified from the steps, starting from the given prior
//        (C_m rho V, rendering_limits.h) and kept within [kMinMassShare, kMaxMassShare] of it.
//        Over the last kWindow frames, per axis with the intercept and the velocity partialled
//        out (Frisch-Waugh), the force's slope against -a_k, pooled over the axes; kept when the
//        window's accelerations hardly differ. The engine's own added mass differs from the
//        prior with the grid (0.80 at 20^3, 0.92 at 32^3 for r = 0.1 m in water); a prior left
//        in the model kept (prior - engine's) a_k in the steady part, and a_k is the velocity
//        change over the step's own dt, which a slow simulation clamps (max_sim_dt 0.05 s against
//        0.4 s of wall time at 48^3 here): held for the step and low-passed, that residual pushed
//        along the acceleration and the hand felt 0.50-0.73 of the engine's added mass.
//   B    drag (N s/m per axis, <= 0: dissipative, at most max_drag in size), the least-squares
//        slope over the last kWindow frames of the force with the added-mass reaction taken out,
//        F_k + m_a a_k, against the probe velocity v_k; an axis whose velocities in the window
//        hardly differ (a steady push) keeps its last slope instead of forgetting it
//   F_s  the steady part (buoyancy, the flow's push): what the newest step's force leaves,
//        F_k + m_a a_k - B v_k
// where a_k = (v_k - v_{k-1}) / T_k is the probe acceleration the step saw (its velocity change
// over its own time step T_k). At the state of the newest step the model returns that step's
// force exactly; between steps it follows the probe's velocity and acceleration.
#include <array>

#include <glm/glm.hpp>

namespace hf::haptics {

class FluidModel {
 public:
  static constexpr int kWindow = 8;  // frames in the drag and added-mass fits
  static constexpr double kMinMassShare = 0.5;   // identified added mass within these shares of the prior
  static constexpr double kMaxMassShare = 1.5;
  static constexpr double kMinAccelSpread = 0.05;  // m/s^2 rms (velocity partialled out): below, keep m_a

  // added_mass_kg >= 0: the prior of the added mass (0: none, not identified); max_drag_n_s_m > 0
  // (the largest |B| per axis the model keeps).
  explicit FluidModel(double added_mass_kg = 0.0, double max_drag_n_s_m = 1e30);

  // One simulation step: its force (N), the probe velocity it used (m/s) and its time step (s;
  // <= 0: unknown, the acceleration term is then left out for this frame).
  void addFrame(const glm::vec3& force_n, const glm::vec3& velocity_m_s, double step_s);
  glm::vec3 force(const glm::vec3& velocity_m_s, const glm::vec3& accel_m_s2) const {
    return steady_n_ + drag_n_s_m_ * velocity_m_s - static_cast<float>(mass_kg_) * accel_m_s2;
  }
  const glm::vec3& steadyN() const { return steady_n_; }
  const glm::vec3& dragNsM() const { return drag_n_s_m_; }   // <= 0 per axis
  double addedMassKg() const { return mass_kg_; }         // identified (the prior until identified)
  double priorAddedMassKg() const { return added_mass_kg_; }
  const glm::vec3& lastAccelM_s2() const { return accel_m_s2_; }
  int frames() const { return frames_; }
  void reset();

 private:
  double added_mass_kg_;
  double max_drag_n_s_m_;
  void fitMass();
  void fitDrag();
  std::array<glm::vec3, kWindow> forces_{}, velocities_{}, accels_{};
  double mass_kg_;
  int held_ = 0, next_ = 0;
  glm::vec3 steady_n_{0.0f}, drag_n_s_m_{0.0f}, accel_m_s2_{0.0f}, last_velocity_m_s_{0.0f};
  int frames_ = 0;
};

}  // namespace hf::haptics
