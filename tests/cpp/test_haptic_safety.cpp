// SPDX-License-Identifier: GPL-3.0-or-later
// The safety stage, unit by unit and through the force pipeline, with injected faults.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "common/error.h"
#include "haptics/rendering/force_pipeline.h"
#include "haptics/rendering/force_safety.h"

namespace hf::haptics {
namespace {

constexpr double kDt = 1e-3;

SafetySettings quickSettings() {
  SafetySettings s;
  s.max_force_n = 3.0f;
  s.slew_rate_n_s = 100.0f;  // 0.1 N per 1 ms period
  s.ramp_s = 0.0;
  s.stale_after_s = 0.1;
  s.fade_s = 0.2;
  return s;
}

TEST(HapticSafetyUnits, ClampMagnitudeKeepsDirectionAndBound) {
  const glm::vec3 v = clampMagnitude(glm::vec3(30.0f, 40.0f, 0.0f), 5.0f);
  EXPECT_LE(glm::length(v), 5.0f);
  EXPECT_NEAR(glm::length(v), 5.0f, 1e-4f);
  EXPECT_NEAR(v.x / v.y, 0.75f, 1e-6f);
  const glm::vec3 small(0.1f, -0.2f, 0.3f);
  EXPECT_EQ(clampMagnitude(small, 5.0f), small);
}

TEST(HapticSafetyUnits, RampAndStaleFactorsAreLinearAndBounded) {
  EXPECT_DOUBLE_EQ(rampFactor(0.0, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(rampFactor(0.5, 2.0), 0.25);
  EXPECT_DOUBLE_EQ(rampFactor(3.0, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(rampFactor(0.0, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(staleFactor(0.05, 0.1, 0.2), 1.0);
  EXPECT_DOUBLE_EQ(staleFactor(0.2, 0.1, 0.2), 0.5);
  EXPECT_DOUBLE_EQ(staleFactor(0.5, 0.1, 0.2), 0.0);
}

TEST(HapticSafetyUnits, StaleThresholdFollowsTheSimulationRate) {
  SafetySettings s = quickSettings();  // stale_after 0.1 s; 3 periods, at most 3 s by default
  EXPECT_DOUBLE_EQ(staleAfterS(s, 0.0), 0.1);     // rate not measured yet: the floor
  EXPECT_DOUBLE_EQ(staleAfterS(s, std::numeric_limits<double>::quiet_NaN()), 0.1);
  EXPECT_DOUBLE_EQ(staleAfterS(s, 100.0), 0.1);   // 3 periods = 30 ms: the floor holds
  EXPECT_DOUBLE_EQ(staleAfterS(s, 4.0), 0.75);    // 3 periods of a 4 Hz simulation
  EXPECT_DOUBLE_EQ(staleAfterS(s, 0.1), 3.0);     // 30 s: bounded by stale_after_max
  s.stale_periods = 2.0;
  s.stale_after_max_s = 0.5;
  EXPECT_DOUBLE_EQ(staleAfterS(s, 10.0), 0.2);
  EXPECT_DOUBLE_EQ(staleAfterS(s, 1.0), 0.5);
  s.stale_after_s = 0.8;  // a floor above the bound: the floor wins (stale_after alone still works)
  EXPECT_DOUBLE_EQ(staleAfterS(s, 1.0), 0.8);
  // Through the stage: a 4 Hz simulation's 0.5 s old force is whole; 0.75 + 0.1 s old, half.
  ForceSafety safety(quickSettings());
  SafetyInput in;
  in.force_n = glm::vec3(1.0f, 0.0f, 0.0f);
  in.homed = true;
  in.sim_rate_hz = 4.0;
  in.dt_s = 1.0;  // a slew step larger than any change: the target is reached at once
  in.force_age_s = 0.5;
  EXPECT_NEAR(safety.apply(in).x, 1.0f, 1e-6f);
  EXPECT_DOUBLE_EQ(safety.staleAfter(), 0.75);
  in.force_age_s = 0.85;
  EXPECT_NEAR(safety.apply(in).x, 0.5f, 1e-6f);
}

TEST(HapticSafetyUnits, BadSettingsAreRejected) {
  SafetySettings s = quickSettings();
  s.max_force_n = -1.0f;
  EXPECT_THROW(s.validate(), InvalidArgument);
  s = quickSettings();
  s.slew_rate_n_s = 0.0f;
  EXPECT_THROW(s.validate(), InvalidArgument);
  s = quickSettings();
  s.fade_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(s.validate(), InvalidArgument);
  for (double periods : {0.5, 0.0, kMaxStalePeriods * 2.0, std::numeric_limits<double>::infinity()}) {
    s = quickSettings();
    s.stale_periods = periods;
    EXPECT_THROW(s.validate(), InvalidArgument) << periods;
  }
  for (double bound : {0.0, -1.0, kMaxStaleS * 2.0, std::numeric_limits<double>::quiet_NaN()}) {
    s = quickSettings();
    s.stale_after_max_s = bound;
    EXPECT_THROW(s.validate(), InvalidArgument) << bound;
  }
}

TEST(HapticSafety, NoOutputAboveTheMaximum) {
  SafetySettings s = quickSettings();
  s.slew_rate_n_s = 1e6f;  // so only the clamp can bound the output
  ForceSafety safety(s);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> huge(-1e4f, 1e4f);
  for (int i = 0; i < 5000; ++i) {
    SafetyInput in;
    in.force_n = glm::vec3(huge(rng), huge(rng), huge(rng));
    in.dt_s = kDt;
    in.homed = true;
    const glm::vec3 out = safety.apply(in);
    ASSERT_LE(glm::length(out), s.max_force_n) << "tick " << i;
  }
  EXPECT_GT(glm::length(safety.last()), 0.9f * s.max_force_n);  // it did push against the bound
}

TEST(HapticSafety, NoStepAboveTheSlewLimit) {
  const SafetySettings s = quickSettings();
  ForceSafety safety(s);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> jump(-50.0f, 50.0f);
  glm::vec3 previous(0.0f);
  const float max_step = s.slew_rate_n_s * static_cast<float>(kDt);
  float largest = 0.0f;
  for (int i = 0; i < 5000; ++i) {
    SafetyInput in;
    // Square waves and random jumps: the worst inputs for a slew limit.
    in.force_n = (i / 200) % 2 ? glm::vec3(jump(rng), jump(rng), jump(rng)) : glm::vec3((i / 50) % 2 ? 40.0f : -40.0f);
    in.dt_s = kDt;
    in.homed = true;
    const glm::vec3 out = safety.apply(in);
    const float step = glm::length(out - previous);
    largest = std::max(largest, step);
    ASSERT_LE(step, max_step * (1.0f + 1e-5f)) << "tick " << i;
    previous = out;
  }
  EXPECT_GT(largest, 0.9f * max_step);  // the limit was reached, not just respected
}

TEST(HapticSafety, FadesToZeroWhenTheSimulationForceIsStale) {
  const SafetySettings s = quickSettings();
  ForceSafety safety(s);
  SafetyInput in;
  in.force_n = glm::vec3(0.0f, 0.0f, 1.0f);
  in.dt_s = kDt;
  in.homed = true;
  for (int i = 0; i < 100; ++i) safety.apply(in);  // settle at 1 N (slew 0.1 N/ms)
  EXPECT_NEAR(safety.last().z, 1.0f, 1e-6f);
  // The simulation stalls: the force it published gets older every period.
  float previous = safety.last().z;
  for (int i = 1; i <= 400; ++i) {
    in.force_age_s = 0.05 + i * kDt;
    const float z = safety.apply(in).z;
    const double expected = staleFactor(in.force_age_s, s.stale_after_s, s.fade_s);
    ASSERT_NEAR(z, expected, 1e-5) << "age " << in.force_age_s;
    ASSERT_LE(z, previous + 1e-7f);
    previous = z;
  }
  EXPECT_EQ(safety.last(), glm::vec3(0.0f));  // 0.45 s old > 0.1 + 0.2 s: nothing left
}

TEST(HapticSafety, NonFiniteForceGivesExactlyZero) {
  ForceSafety safety(quickSettings());
  SafetyInput in;
  in.force_n = glm::vec3(1.0f);
  in.dt_s = kDt;
  in.homed = true;
  for (int i = 0; i < 50; ++i) safety.apply(in);
  ASSERT_GT(glm::length(safety.last()), 0.5f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  in.force_n = glm::vec3(0.5f, nan, 0.5f);
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));
  in.force_n = glm::vec3(-inf, 0.0f, 0.0f);
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));
  EXPECT_EQ(safety.nonFiniteCount(), 2u);
  in.force_n = glm::vec3(1.0f);
  in.force_age_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));
}

TEST(HapticSafety, NothingBeforeHomingThenARampIn) {
  SafetySettings s = quickSettings();
  s.ramp_s = 2.0;
  s.slew_rate_n_s = 1e4f;
  ForceSafety safety(s);
  SafetyInput in;
  in.force_n = glm::vec3(2.0f, 0.0f, 0.0f);
  in.dt_s = kDt;
  in.homed = false;
  for (int i = 0; i < 3000; ++i) ASSERT_EQ(safety.apply(in), glm::vec3(0.0f)) << "tick " << i;
  in.homed = true;
  for (int i = 1; i <= 2500; ++i) {
    const double t = i * kDt;
    const float x = safety.apply(in).x;
    ASSERT_NEAR(x, 2.0 * rampFactor(t, s.ramp_s), 1e-4) << "t " << t;
  }
  EXPECT_NEAR(safety.last().x, 2.0f, 1e-6f);
  in.homed = false;  // homing lost: zero at once, and the ramp starts over
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));
  in.homed = true;
  EXPECT_NEAR(safety.apply(in).x, 2.0 * kDt / s.ramp_s, 1e-6);
}

// Pause or stop (output disabled) brings the force down at the slew rate, not in one step: a
// hand pushing against 3 N must not be thrown by the force vanishing; then the ramp starts over.
TEST(HapticSafety, DisabledOutputSlewsDownToZeroAndTheRampStartsOver) {
  SafetySettings s = quickSettings();
  s.ramp_s = 0.5;
  ForceSafety safety(s);
  SafetyInput in;
  in.force_n = glm::vec3(0.0f, 10.0f, 0.0f);  // clamped to 3 N
  in.dt_s = kDt;
  in.homed = true;
  for (int i = 0; i < 1000; ++i) safety.apply(in);
  ASSERT_NEAR(safety.last().y, 3.0f, 1e-4f);
  in.enabled = false;
  const float max_step = s.slew_rate_n_s * static_cast<float>(kDt);
  glm::vec3 previous = safety.last();
  int ticks = 0;
  while (safety.last() != glm::vec3(0.0f)) {
    ASSERT_LT(++ticks, 1000) << "never reached zero";
    const glm::vec3 out = safety.apply(in);
    ASSERT_LE(glm::length(out - previous), max_step * (1.0f + 1e-5f)) << "tick " << ticks;
    ASSERT_LT(glm::length(out), glm::length(previous));
    previous = out;
  }
  EXPECT_NEAR(ticks, 30, 1);  // 3 N at 0.1 N per period
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));  // and stays there
  in.enabled = true;  // resumed: the ramp starts over
  EXPECT_NEAR(safety.apply(in).y, 10.0 * kDt / s.ramp_s, 1e-6);  // the wanted 10 N, ramped
  in.enabled = false;
  in.dt_s = std::numeric_limits<double>::quiet_NaN();  // no valid period: zero at once
  EXPECT_EQ(safety.apply(in), glm::vec3(0.0f));
}

// The same properties through the whole pipeline, faults injected in its inputs.
PipelineSettings pipelineSettings() {
  PipelineSettings p;
  p.safety = quickSettings();
  p.filter.enabled = false;
  p.map.force_gain = 2.0f;
  return p;
}

TickInput tickAt(double t, const glm::vec3& force, double published_s, bool homed = true) {
  TickInput in;
  in.now_s = t;
  in.dt_s = kDt;
  in.state.homed = homed;
  in.have_force = true;
  in.force.force_n = force;
  in.force.publish_time_s = published_s;
  in.force.sim_rate_hz = 30.0;
  return in;
}

TEST(HapticPipelineFaults, NaNFromTheSimulationNeverReachesTheDevice) {
  ForcePipeline pipe(pipelineSettings());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 200; ++i) pipe.tick(tickAt(i * kDt, glm::vec3(1.0f, 0.0f, 0.0f), i * kDt));
  const TickOutput bad = pipe.tick(tickAt(0.2, glm::vec3(nan), 0.2));
  EXPECT_EQ(bad.commanded_n, glm::vec3(0.0f));
  // Filter on too: the NaN does not stay in its memory.
  PipelineSettings p = pipelineSettings();
  p.filter.enabled = true;
  ForcePipeline filtered(p);
  filtered.tick(tickAt(0.0, glm::vec3(nan), 0.0));
  const TickOutput after = filtered.tick(tickAt(kDt, glm::vec3(1.0f), kDt));
  EXPECT_TRUE(allFinite(after.commanded_n));
  EXPECT_TRUE(allFinite(after.filtered_n));
}

TEST(HapticPipelineFaults, StalledSimulationFadesAndUnhomedDeviceGetsNothing) {
  ForcePipeline pipe(pipelineSettings());
  // Frames published on time for 0.2 s, then the simulation stalls at t = 0.2 s.
  glm::vec3 out(0.0f);
  for (int i = 0; i < 1000; ++i) {
    const double t = i * kDt;
    out = pipe.tick(tickAt(t, glm::vec3(1.0f, 0.0f, 0.0f), std::min(t, 0.2))).commanded_n;
    if (t > 0.2 + 0.1 + 0.2 + kDt) {
      ASSERT_EQ(out, glm::vec3(0.0f)) << "t " << t;
    }
  }
  ForcePipeline unhomed(pipelineSettings());
  for (int i = 0; i < 500; ++i) {
    ASSERT_EQ(unhomed.tick(tickAt(i * kDt, glm::vec3(1.0f), i * kDt, false)).commanded_n, glm::vec3(0.0f));
  }
}

}  // namespace
}  // namespace hf::haptics
