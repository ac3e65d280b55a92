// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PassivityController: a time-domain passivity observer and controller (Hannaford and Ryu 2002)
// on the haptic loop, one call per period, free of threads and clocks (tested sample by sample).
//
// Sign convention: energy is counted positive when it flows from the device INTO THE HAND. A
// passive rendering can only give back what the hand put in, so the sum over a session stays
// <= 0 (up to what the fluid still stores); a positive sum means the loop (delay, sampling) has
// made energy.
//   observer   E(n) = E(n-1) + F(n-1) . (x(n) - x(n-1))
//              F(n-1) is the force the device held since the previous reading (after safety),
//              x the device position: the exact work of a held force, no velocity estimate.
//   memory     stored dissipation (E < 0) decays towards 0 with time constant reserve_decay_s
//              and is never more than max_reserve_j, so dissipation from long ago cannot
//              license a later burst of energy.
//   controller this period's wanted force F adds E_p = E(n) + F . v dt to the observer; if
//              E_p > 0 a damper removes it:  F' = F - alpha v,  alpha = E_p / (|v|^2 dt),
//              bounded by max_damping_n_s_m (the device's maximum stable damping). If the
//              bounded damper cannot remove all of it, the force's push along the motion is
//              cut back, to zero at most (F' -= c v/|v|, 0 <= c <= F' . v/|v|): that removes
//              energy without rendering a stiffer damper (it never pushes against the motion
//              beyond the bounded damper). Below the velocity dead-band nothing is applied
//              (alpha would be huge on noise); the excess stays observed and is removed once
//              the hand moves. A device that reports no maximum damping is observed only.
// Slew-aware (given the safety stage's slew rate S): the safety stage changes the force by at
// most S dt per period, so a correction asked for now arrives late; at a high gain the push kept
// while it slews in was enough to keep a hand swinging. So the controller plans around it:
//   - it checks the force the device will actually hold this period, slewLimit(held, wanted),
//     not the wanted one;
//   - it counts the energy still to come while a push p along the motion is slewed back to zero,
//     p^2 |v| / (2 S'), S' = kPlanSlewFraction S (margin for a speed that grows meanwhile and for
//     the sideways share of the step): the budget is E + p |v| dt + p^2 |v| / (2 S') <= 0, so the
//     push is taken back while the stored dissipation can still pay for the unwinding;
//   - through the slew step, the change along the motion goes first (a sideways change of the
//     wanted force does not use up the step that takes the push back).
// Acceleration-aware (the turn-around): a force AGAINST the motion dissipates, so the budget
// allows it, but when the hand turns round it becomes a push, and a hand that speeds up while
// that push slews back takes energy from it: p^2 |v| / (2 S') + a p^3 / (6 S'^2) for a push p
// unwound from speed |v| with acceleration a along the motion (the integral of (p - S't)(|v| + a t)
// over the unwinding). With a the hand's acceleration (the velocity readings differentiated and
// low-passed over kAccelFilterS):
//   - pushing and speeding up (a > 0 along the motion): the cubic term joins the budget, so the
//     allowed push is the root of E + p |v| dt + p^2 |v| / (2 S') + a p^3 / (6 S'^2) = 0;
//   - against the motion and slowing down (a < 0 along it): the hand turns in t = |v| / |a|.
//     By then the force against the motion must be down to q_turn = cbrt(6 S'^2 (A - E) / |a|),
//     the push the stored dissipation can unwind after the turn (A = kTurnAllowanceJ, so noise
//     in a slow, steady hold does not blank a steady force); the slew limit takes S' t of it off
//     on the way, so now the force against the motion is held to q_turn + S' t: what is above is
//     taken off first along the motion (this removes dissipation, never adds energy now).
//   A turn measured in one run (gain 1, 300 N/m hand): 4 N against a hand stopping at 10 m/s^2
//   became a 6 N push after the turn and gave the hand 16 mJ in 30 ms before this plan.
// With no slew limit (S = 0) it is the plain controller above: the same damping, to the bit.
// It sits before the safety stage: clamp and slew limit stay the last word on |F|. The pipeline
// hands it the wanted force already clamped to max_force (the force the device can deliver), and
// the final clamp only scales the result, which keeps the sign of its power. Whatever safety
// does to it (ramp, stale fade, slew) is seen by the observer next period, because it observes
// the force the device actually held.
// Reset (observer, damper, memory): at (re)start, while the device is not homed, and when the
// output is off (paused, stopping or failed with the force slewed to zero).
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

namespace hf::haptics {

// The controller plans the unwinding of a push with this fraction of the safety stage's slew rate.
inline constexpr double kPlanSlewFraction = 0.5;
// The hand's acceleration: the velocity readings differentiated, low-passed with this time
// constant (s): short beside a turn (a 10 m/s^2 stop from 0.2 m/s takes 20 ms), long beside the
// 1 ms period.
inline constexpr double kAccelFilterS = 0.004;
// Energy a turn may leak beyond the stored dissipation (J): 0.1 mJ, so a slow hold whose
// acceleration is velocity noise keeps a steady force (about 1.8 N at 1 m/s^2 of noise with
// nothing stored) while a real turn at 10 m/s^2 is held to 0.84 N at the turn with nothing
// stored, 3.9 N with the whole 10 mJ reserve (S' = 100 N/s).
inline constexpr double kTurnAllowanceJ = 1e-4;

struct PassivitySettings {
  bool enabled = true;                    // false: observe only (no damping)
  // Largest damping the controller adds, N s/m (> 0). None: the device's maximum stable damping
  // (DeviceInfo::max_damping_n_s_m), filled in by the haptic loop; with a device that reports
  // none (virtual devices) it stays None and the loop is observed only.
  std::optional<float> max_damping_n_s_m;
  // Below this speed nothing is applied, m/s (>= 0). What the loop can still put in is at most
  // |F| x this (8 mW at 8 N); the Falcon's encoder (about 0.04 mm per count) read through the
  // driver's 15 ms velocity filter jitters up to ~2.5 mm/s, so below that noise may trigger small
  // corrections while the loop owes energy (only then does the controller act at all).
  float velocity_deadband_m_s = 0.001f;
  double max_reserve_j = 0.01;            // most stored dissipation kept, J (>= 0)
  double reserve_decay_s = 0.5;           // stored dissipation decays with this time constant, s (> 0)
  void validate() const;                  // throws InvalidArgument naming the bad value
};

struct PassivityState {                   // published to the host (trivially copyable)
  double energy_j = 0.0;                  // observer E(n): > 0 means net energy made by the loop
  double delivered_j = 0.0;               // plain sum of F . dx into the hand since the last reset, J
  double dissipated_j = 0.0;              // energy removed (damper and cut) since the last reset, J
  double alpha_n_s_m = 0.0;               // this period's damping, N s/m
  double cut_n = 0.0;                     // this period's cut of the push along the motion, N
  std::uint64_t active = 0;               // periods with damping or a cut since the last reset
  std::uint64_t turn_ticks = 0;           // of those, periods that eased a force against the motion before a turn
  std::uint64_t resets = 0;               // resets after something was observed
};

class PassivityController {
 public:
  // slew_rate_n_s: the safety stage's slew limit after this controller (N/s, >= 0; 0: none).
  explicit PassivityController(const PassivitySettings& s, float slew_rate_n_s = 0.0f);

  // One haptic period. wanted_n: the force this period wants (device frame, N, before safety);
  // position_m, velocity_m_s: this period's device reading; held_n: the force the device held
  // since the previous reading (the safety stage's last output, N); dt_s: the period (s).
  // gate_speed_m_s: the speed held against the velocity dead-band (m/s; < 0, the default: |velocity|),
  // e.g. a quieter estimate of the same motion, so noise in the velocity the damper acts on does
  // not open the gate. Returns the force to hand to the safety stage: wanted_n itself when the
  // controller does not act. A non-finite input is passed through unchanged (safety zeroes it) and
  // not observed.
  glm::vec3 apply(const glm::vec3& wanted_n, const glm::vec3& position_m, const glm::vec3& velocity_m_s,
                  const glm::vec3& held_n, double dt_s, double gate_speed_m_s = -1.0);
  void reset();
  const PassivityState& state() const { return st_; }
  bool acted() const { return acted_; }  // this period: damped, cut or slewed the push back first
  const PassivitySettings& settings() const { return s_; }

 private:
  // J still to come while a push is slewed back from speed |v| with acceleration a (>= 0) along the motion.
  double unwindEnergy(double push_n, double speed_m_s, double accel_m_s2) const;
  // N along the motion: the largest push the budget E + p |v| dt + unwind(p) <= 0 allows.
  double allowedPush(double energy_j, double speed_m_s, double accel_m_s2, double dt_s) const;
  // N against the motion the hand may still feel now, slowing down at decel_m_s2 (> 0) (see the header).
  double allowedAgainst(double energy_j, double speed_m_s, double decel_m_s2) const;
  void trackAcceleration(const glm::vec3& velocity_m_s, double dt_s);

  PassivitySettings s_;
  float slew_rate_n_s_ = 0.0f;
  PassivityState st_;
  bool acted_ = false;
  bool have_position_ = false;
  glm::dvec3 last_position_m_{0.0};
  bool have_velocity_ = false;
  glm::dvec3 last_velocity_m_s_{0.0};
  glm::dvec3 accel_m_s2_{0.0};             // low-passed (kAccelFilterS)
};

}  // namespace hf::haptics
