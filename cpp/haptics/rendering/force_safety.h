// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The safety stage between the filtered force and the device, as small units (each tested alone)
// and ForceSafety, which chains them once per haptic period:
//   not homed                    -> zero now, and the ramp starts again when force may resume
//   output disabled (pause, stop, a failed simulation, no force yet)
//                                -> down to zero at the slew rate (max_force / slew_rate at
//                                   most, 40 ms for 8 N at 200 N/s); the ramp starts again
//   NaN or Inf anywhere          -> zero now (counted)
//   stale simulation force       -> faded linearly to zero (age past the stale threshold, over
//                                   fade_s); the threshold follows the simulation: stale_periods
//                                   of its measured period, within [stale_after_s,
//                                   stale_after_max_s] (staleAfterS), so a 4 Hz simulation's force
//                                   reaches the hand between its frames and a stalled one fades
//   ramp-in                      -> scaled by t / ramp_s for ramp_s after force (re)starts
//   clamp                        -> |F| <= max_force_n (already the device's max at most)
//   slew limit                   -> |F - F_previous| <= slew_rate_n_s * dt, up or down; the hard
//                                   stops above (not homed, NaN: zero now) are the only exception.
#include <cstdint>

#include <glm/glm.hpp>

#include "common/finite.h"

namespace hf::haptics {

// Longest wind-down of the force on stop() (max_force / slew_rate), s. validate() refuses a
// slew rate slower than that, so stop() always slews the whole way down to zero; the haptic
// loop ends a wind-down early only after twice the periods this takes at the nominal rate.
inline constexpr double kMaxWindDownS = 2.0;

// Longest stale_after_s and fade_s, s: a simulation force older than this is stale however slow
// the simulation (a larger value would all but turn the stale fade off).
inline constexpr double kMaxStaleS = 10.0;

// Most simulation periods a force may age before it is stale (more would hide a stall).
inline constexpr double kMaxStalePeriods = 100.0;

struct SafetySettings {
  float max_force_n = 5.0f;       // |commanded force| bound, N (> 0)
  float slew_rate_n_s = 200.0f;   // largest change of the commanded force per second, N/s
                                  // (>= max_force_n / kMaxWindDownS)
  double ramp_s = 2.0;            // ramp-in after (re)start, s (>= 0)
  // A simulation force starts fading when older than stale_periods measured simulation periods,
  // at least stale_after_s and at most max(stale_after_s, stale_after_max_s) (the bound a stalled
  // simulation meets); stale_after_s alone while the rate is unknown (0: before it is measured).
  double stale_after_s = 0.1;     // s (0 .. kMaxStaleS]
  double stale_periods = 3.0;     // simulation periods [1 .. kMaxStalePeriods]
  double stale_after_max_s = 3.0; // s (0 .. kMaxStaleS]
  double fade_s = 0.2;            // ... and reaches zero this much later, s (0 .. kMaxStaleS]
  void validate() const;          // throws InvalidArgument naming the bad value
};

using hf::allFinite;  // common/finite.h
glm::vec3 clampMagnitude(const glm::vec3& v, float max_n);
glm::vec3 slewLimit(const glm::vec3& previous, const glm::vec3& target, float max_step_n);
double rampFactor(double since_start_s, double ramp_s);             // 0 .. 1
double staleFactor(double age_s, double stale_after_s, double fade_s);  // 1 .. 0
// The age (s) at which a force from a simulation stepping at sim_rate_hz starts fading:
// stale_periods / rate within [stale_after_s, max(stale_after_s, stale_after_max_s)]; stale_after_s for a rate that
// is not a positive finite number (not measured yet).
double staleAfterS(const SafetySettings& s, double sim_rate_hz);

struct SafetyInput {
  glm::vec3 force_n{0.0f};   // wanted force (device frame, N)
  double dt_s = 0.001;       // haptic period, s (not finite or <= 0: the force holds still)
  double force_age_s = 0.0;  // age of the simulation force behind it, s
  double sim_rate_hz = 0.0;  // the simulation's measured rate when it published it (0: unknown)
  bool homed = false;
  bool enabled = true;       // false: paused, failed or stopping
};

class ForceSafety {
 public:
  explicit ForceSafety(const SafetySettings& s) : s_(s) {}
  glm::vec3 apply(const SafetyInput& in);
  void reset();
  // True while the ramp-in after a (re)start has not reached full scale: the latest apply() scaled
  // its force by less than 1, or force has not (re)started since. The coupled rendering renders its
  // steady part alone meanwhile (force_pipeline.h).
  bool rampingIn() const { return ramp() < 1.0; }
  double staleAfter() const { return stale_after_s_; }  // the threshold of the latest apply(), s
  std::uint64_t nonFiniteCount() const { return non_finite_; }
  const glm::vec3& last() const { return last_; }
  const SafetySettings& settings() const { return s_; }

 private:
  double ramp() const { return rampFactor(ramp_time_s_, s_.ramp_s); }  // this ramp-in's scale, 0 .. 1

  SafetySettings s_;
  glm::vec3 last_{0.0f};
  double ramp_time_s_ = 0.0;  // time since force was last allowed to start
  double stale_after_s_ = 0.0;
  std::uint64_t non_finite_ = 0;
};

}  // namespace hf::haptics
