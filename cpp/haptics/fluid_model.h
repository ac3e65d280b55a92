#pragma once
// FluidModel: the local model of the fluid's force on the probe (the intermediate representation
// of Adachi et al. 1995 and Mark et al. 1996), identified from every simulation step and evaluated
// at the haptic rate against the probe's own motion (fluid frame, SI):
//   F(v, a) = F_s + B v - m_a a
//   m_a  the probe's added mass (kg, given: C_m rho V, rendering_limits.h), per unit acceleration
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
  static constexpr int kWindow = 8;  // frames in the drag fit

  // added_mass_kg >= 0; max_drag_n_s_m > 0 (the largest |B| per axis the model keeps).
  explicit FluidModel(double added_mass_kg = 0.0, double max_drag_n_s_m = 1e30);

  // One simulation step: its force (N), the probe velocity it used (m/s) and its time step (s;
  // <= 0: unknown, the acceleration term is then left out for this frame).
  void addFrame(const glm::vec3& force_n, const glm::vec3& velocity_m_s, double step_s);
  glm::vec3 force(const glm::vec3& velocity_m_s, const glm::vec3& accel_m_s2) const {
    return steady_n_ + drag_n_s_m_ * velocity_m_s - static_cast<float>(added_mass_kg_) * accel_m_s2;
  }
  const glm::vec3& steadyN() const { return steady_n_; }
  const glm::vec3& dragNsM() const { return drag_n_s_m_; }   // <= 0 per axis
  double addedMassKg() const { return added_mass_kg_; }
  const glm::vec3& lastAccelM_s2() const { return accel_m_s2_; }
  int frames() const { return frames_; }
  void reset();

 private:
  double added_mass_kg_;
  double max_drag_n_s_m_;
  void fitDrag();
  std::array<glm::vec3, kWindow> rests_{}, velocities_{};
  int held_ = 0, next_ = 0;
  glm::vec3 steady_n_{0.0f}, drag_n_s_m_{0.0f}, accel_m_s2_{0.0f}, last_velocity_m_s_{0.0f};
  int frames_ = 0;
};

}  // namespace hf::haptics
