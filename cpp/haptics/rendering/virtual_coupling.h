// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// VirtualCoupling: a proxy carrying the fluid's local model (fluid_model.h), integrated at the
// haptic rate and coupled to the hand by a spring-damper (Colgate, Stanley and Brown 1995; Adams
// and Hannaford 1999). Device frame, per axis (the map is diagonal, so the axes do not mix):
//   proxy       M a_p = F_ext - D v_p + F_c          M: the rendered added mass (kg), D >= 0 the
//                                                    rendered drag (N s/m), F_ext the steady force
//   coupling    F_c = K (x_h - x_p) + B (v_h - v_p)  pulls the proxy towards the hand
//   hand        feels -F_c
// Implicit Euler for the proxy (v_p and x_p at the end of the period in F_c and in the drag), so
// the proxy is stable and dissipative for any M >= 0 and D >= 0; the hand touches only the
// coupling, whose K and B stay inside the device's stable stiffness and damping. A passive
// virtual medium behind such a coupling stays passive at the handle, whatever M and D are: the
// force gain no longer has to keep the rendered mass and drag small (rendering_limits.h).
// At rest the proxy settles where the spring holds F_ext, so the hand feels the steady force; a
// hand that starts moving stretches the spring in the very period it moves, so the force
// answers the hand's motion within one haptic period, with or without a new simulation step.
#include <glm/glm.hpp>

namespace hf::haptics {

// The coupling takes these shares of the device's maximum stable stiffness and damping when the
// settings leave them at 0 (the Falcon: 750 N/m, 10 N s/m): a spring and a damper at their limits
// together are not stable, so each gets a part. A stiff spring also turns the encoder's counts
// into force steps that a resting hand turns into energy (1/2 K dx^2 per count crossed): on the
// simulated Falcon (20^3 water, gain 0.08, resting 300 N/m hand, 5 s) 1500 N/m and 5 N s/m gave
// 3.3 mJ, 750 N/m and 10 N s/m 0.6 mJ (docs/ARCHITECTURE.md, Force at the haptic rate).
inline constexpr float kCouplingStiffnessShare = 0.25f;
inline constexpr float kCouplingDampingShare = 0.5f;

struct CouplingSettings {
  bool enabled = true;          // false: the seed's rendering (the low-passed step force)
  float stiffness_n_m = 0.0f;   // K (N/m, >= 0); 0: kCouplingStiffnessShare x the device's maximum
  float damping_n_s_m = 0.0f;   // B (N s/m, >= 0); 0: kCouplingDampingShare x the device's maximum
  // The probe's added mass in the fluid (kg, >= 0; the session sets it from the probe and fluid).
  double added_mass_kg = 0.0;
  // True when the coupling renders: enabled, with a stiffness (a device that reports no rendering
  // limits, a virtual one, keeps the seed's rendering).
  bool active() const { return enabled && stiffness_n_m > 0.0f; }
  void validate() const;        // throws InvalidArgument naming the bad value
};

class VirtualCoupling {
 public:
  VirtualCoupling(float stiffness_n_m, float damping_n_s_m) : k_(stiffness_n_m), b_(damping_n_s_m) {}

  // One haptic period of dt_s: the hand's position (m) and velocity (m/s); the proxy's mass (kg,
  // >= 0), drag (N s/m, >= 0) and steady force (N). Returns the force on the hand (N). The first
  // call after reset() puts the proxy at the hand, at rest. A mass that changes (the local model
  // identifies it from the steps) never adds kinetic energy: a larger mass keeps the proxy's
  // momentum (its energy falls by the ratio of the masses), a smaller one keeps its velocity.
  glm::vec3 step(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& mass_kg,
                 const glm::vec3& drag_n_s_m, const glm::vec3& external_n, double dt_s);
  void reset() { placed_ = false; }
  // Puts the proxy where the spring holds external_n against a hand at hand_m, moving with it:
  // nothing stored but the steady force's own spring stretch. The pipeline keeps the proxy placed
  // while the safety stage ramps the force in, so a ramp that scales the output never releases,
  // at full scale, energy the proxy stored while the hand felt a fraction of it.
  void place(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& external_n);
  // The force the hand got this period (after the passivity controller and the safety stage),
  // when it differs from step()'s: the spring slips, per axis, to the stretch that gives it,
  // where that stretch is smaller (the proxy never feels what the hand did not: a cut force
  // that still pulled the proxy along would hand its energy back to the hand later). A slip that
  // would stretch the spring is not taken (no energy is ever added).
  void yieldTo(const glm::vec3& hand_m, const glm::vec3& hand_m_s, const glm::vec3& delivered_n);
  const glm::dvec3& proxyM() const { return x_; }
  const glm::dvec3& proxyM_s() const { return v_; }
  // The proxy's acceleration over the last period (m/s^2).
  const glm::dvec3& proxyM_s2() const { return a_; }

 private:
  double k_, b_;
  bool placed_ = false;
  glm::dvec3 x_{0.0}, v_{0.0}, a_{0.0};
  glm::dvec3 mass_kg_{-1.0};  // the mass of the last step (< 0: none yet)
};

}  // namespace hf::haptics
