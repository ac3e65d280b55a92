// SPDX-License-Identifier: GPL-3.0-or-later
// The seed's low-pass (bandwidth following the simulation rate) and the drag predictor.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "haptics/loop/rate_estimator.h"
#include "haptics/rendering/drag_predictor.h"
#include "haptics/rendering/force_pipeline.h"
#include "haptics/rendering/low_pass_filter.h"

namespace hf::haptics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDt = 1e-3;

TEST(HapticLowPass, CutoffFollowsTheRateWithinItsRange) {
  LowPassSettings s;
  s.bandwidth_ratio = 0.5;
  s.min_cutoff_hz = 1.0;
  s.max_cutoff_hz = 200.0;
  EXPECT_DOUBLE_EQ(cutoffForRate(s, 30.0), 15.0);
  EXPECT_DOUBLE_EQ(cutoffForRate(s, 120.0), 60.0);
  EXPECT_DOUBLE_EQ(cutoffForRate(s, 1000.0), 200.0);  // capped
  EXPECT_DOUBLE_EQ(cutoffForRate(s, 0.5), 1.0);       // floored
  EXPECT_DOUBLE_EQ(cutoffForRate(s, 0.0), 1.0);       // unknown rate: heaviest smoothing
}

// Step response through the pipeline at two simulation rates: each matches the analytic
// first-order response 1 - exp(-2 pi fc t) with fc = ratio x rate, so the faster simulation gets
// the proportionally faster filter.
TEST(HapticLowPass, StepResponseMatchesFirstOrderAtTheMeasuredRate) {
  for (const double rate_hz : {20.0, 100.0}) {
    PipelineSettings p;
    p.filter.bandwidth_ratio = 0.5;
    p.safety.max_force_n = 100.0f;
    p.safety.slew_rate_n_s = 1e6f;
    p.safety.ramp_s = 0.0;
    p.safety.stale_after_s = 10.0;
    ForcePipeline pipe(p);
    const double fc = 0.5 * rate_hz;
    double t63 = -1.0;
    for (int i = 1; i <= 300; ++i) {
      TickInput in;
      in.now_s = i * kDt;
      in.dt_s = kDt;
      in.state.homed = true;
      in.have_force = true;
      in.force.force_n = glm::vec3(0.0f, 0.0f, 1.0f);
      in.force.publish_time_s = in.now_s;
      in.force.sim_rate_hz = rate_hz;
      const TickOutput out = pipe.tick(in);
      const double t = i * kDt;
      const double analytic = 1.0 - std::exp(-2.0 * kPi * fc * t);
      ASSERT_NEAR(out.commanded_n.z, analytic, 2e-6) << "rate " << rate_hz << " Hz, t " << t;
      ASSERT_DOUBLE_EQ(out.cutoff_hz, fc);
      if (t63 < 0.0 && out.commanded_n.z >= 1.0 - std::exp(-1.0)) t63 = t;
    }
    // The time constant is 1 / (2 pi fc): 15.9 ms at 20 Hz, 3.2 ms at 100 Hz.
    EXPECT_NEAR(t63, 1.0 / (2.0 * kPi * fc), 1.01 * kDt) << "rate " << rate_hz;
  }
}

TEST(HapticLowPass, ExactForAnyPeriod) {
  LowPassFilter f;
  const double fc = 7.0;
  double t = 0.0;
  for (const double dt : {0.0005, 0.002, 0.001, 0.004}) {
    f.update(glm::vec3(1.0f), dt, fc);
    t += dt;
    EXPECT_NEAR(f.value().x, 1.0 - std::exp(-2.0 * kPi * fc * t), 1e-6);
  }
}

TEST(HapticRateEstimator, ConvergesToTheEventRate) {
  RateEstimator r;
  EXPECT_EQ(r.rateHz(), 0.0);
  for (int i = 0; i < 100; ++i) r.add(i / 40.0);
  EXPECT_NEAR(r.rateHz(), 40.0, 1e-6);
  for (int i = 0; i < 60; ++i) r.add(100 / 40.0 + (i + 1) / 10.0);  // slows to 10 Hz
  EXPECT_NEAR(r.rateHz(), 10.0, 0.01);
}

// A synthetic drag law F = F_b - b v (buoyancy plus drag), evaluated by a "simulation" at 30 Hz
// from the velocity at the start of each frame, while the probe oscillates. Between frames the
// held force lags the true one; the predictor's F0 + B (v - v0) follows it.
TEST(HapticPrediction, ReducesErrorOnADragLaw) {
  const double b = 3.0, buoyancy = 0.4, sim_hz = 30.0;
  const auto velocity = [](double t) { return glm::vec3(0.2 * std::sin(2 * kPi * 1.5 * t), 0.1 * std::cos(2 * kPi * 0.7 * t), 0.0); };
  const auto law = [&](const glm::vec3& v) { return glm::vec3(0.0f, 0.0f, static_cast<float>(buoyancy)) - float(b) * v; };

  PipelineSettings p;
  p.filter.enabled = false;
  p.safety.max_force_n = 100.0f;
  p.safety.slew_rate_n_s = 1e6f;
  p.safety.ramp_s = 0.0;
  p.safety.stale_after_s = 10.0;
  PipelineSettings held = p;
  p.prediction = true;
  ForcePipeline predicted(p), plain(held);

  double err_pred = 0.0, err_held = 0.0;
  ForceFrame frame;
  int frames = 0;
  for (int i = 0; i < 4000; ++i) {
    const double t = i * kDt;
    TickInput in;
    in.now_s = t;
    in.dt_s = kDt;
    in.state.homed = true;
    in.state.velocity_m_s = velocity(t);
    const int k = static_cast<int>(t * sim_hz);
    if (k >= frames) {  // a new simulation frame, computed from the velocity at its start
      frames = k + 1;
      frame.probe_velocity_m_s = velocity(k / sim_hz);
      frame.force_n = law(frame.probe_velocity_m_s);
      frame.publish_time_s = t;
      frame.sim_rate_hz = sim_hz;
      in.new_frame = true;
    }
    in.have_force = true;
    in.force = frame;
    const glm::vec3 truth = law(in.state.velocity_m_s);
    const glm::vec3 a = predicted.tick(in).commanded_n, h = plain.tick(in).commanded_n;
    if (t > 0.5) {  // after the fit has its frames
      err_pred += glm::dot(a - truth, a - truth);
      err_held += glm::dot(h - truth, h - truth);
    }
  }
  EXPECT_NEAR(predicted.predictor().dragNsM().x, -b, 1e-3 * b);
  EXPECT_NEAR(predicted.predictor().dragNsM().y, -b, 1e-3 * b);
  EXPECT_EQ(predicted.predictor().dragNsM().z, 0.0f);  // no velocity spread on z: no fit
  EXPECT_LT(std::sqrt(err_pred), 0.01 * std::sqrt(err_held));  // the law is exactly linear
}

TEST(HapticPrediction, NeverFitsAnEnergyAddingSlope) {
  DragPredictor d;
  for (int i = 0; i < 10; ++i) {
    const glm::vec3 v(0.1f * i, -0.05f * i, 0.0f);
    d.addFrame(2.0f * v, v);  // force along the velocity: B would be +2
  }
  EXPECT_EQ(d.dragNsM(), glm::vec3(0.0f));
  const glm::vec3 last_v(0.1f * 9, -0.05f * 9, 0.0f);
  EXPECT_EQ(d.predict(glm::vec3(5.0f)), 2.0f * last_v);  // F0 held
}

}  // namespace
}  // namespace hf::haptics
