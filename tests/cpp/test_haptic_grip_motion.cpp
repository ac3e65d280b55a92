// SPDX-License-Identifier: GPL-3.0-or-later
// GripMotion: the grip's velocity from the positions the loop reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "haptics/rendering/grip_motion.h"

namespace hf::haptics {
namespace {

TEST(HapticGripMotion, ConstantVelocityIsReadExactlyWithinOnePeriod) {
  GripMotion m;
  EXPECT_EQ(m.update(glm::vec3(0.01f, 0.0f, 0.0f), 0.001), glm::vec3(0.0f));  // one reading: no motion yet
  for (int i = 1; i < 20; ++i) {
    const glm::vec3 v = m.update(glm::vec3(0.01f + 0.2f * 0.001f * i, -0.05f * 0.001f * i, 0.0f), 0.001);
    EXPECT_NEAR(v.x, 0.2f, 1e-3f) << i;  // from the second reading on, not after a filter's lag
    EXPECT_NEAR(v.y, -0.05f, 1e-3f) << i;
    EXPECT_EQ(v.z, 0.0f);
  }
}

TEST(HapticGripMotion, FollowsAStopWithinTheSpanNotAFiltersTimeConstant) {
  GripMotion m;
  double x = 0.0;
  for (int i = 0; i < 20; ++i) m.update(glm::vec3(static_cast<float>(x += 1e-4), 0.0f, 0.0f), 0.001);  // 0.1 m/s
  // The grip stops: after kGripVelocitySpan periods the estimate is exactly zero (the Falcon
  // driver's 15 ms low-pass would still read 0.1 x e^-(span/15) of the speed).
  glm::vec3 v(1.0f);
  for (std::size_t i = 0; i < kGripVelocitySpan; ++i) v = m.update(glm::vec3(static_cast<float>(x), 0.0f, 0.0f), 0.001);
  EXPECT_EQ(v, glm::vec3(0.0f));
}

TEST(HapticGripMotion, UsesTheMeasuredPeriods) {
  GripMotion m;
  m.update(glm::vec3(0.0f), 0.001);
  m.update(glm::vec3(0.001f, 0.0f, 0.0f), 0.002);  // a late period: 1 mm in 2 ms
  EXPECT_NEAR(m.update(glm::vec3(0.0015f, 0.0f, 0.0f), 0.001).x, 0.5f, 1e-4f);  // 1.5 mm in 3 ms
}

TEST(HapticGripMotion, ANonFiniteReadingGivesNanAndRestarts) {
  GripMotion m;
  m.update(glm::vec3(0.0f), 0.001);
  m.update(glm::vec3(0.001f, 0.0f, 0.0f), 0.001);
  EXPECT_TRUE(std::isnan(m.update(glm::vec3(NAN, 0.0f, 0.0f), 0.001).x));
  EXPECT_EQ(m.update(glm::vec3(0.5f, 0.0f, 0.0f), 0.001), glm::vec3(0.0f));  // no jump across the gap
  EXPECT_NEAR(m.update(glm::vec3(0.5001f, 0.0f, 0.0f), 0.001).x, 0.1f, 1e-3f);
}

// Readings quantised to `step` (m), as an encoder gives them.
glm::vec3 quantised(double x, double y, double step) {
  return glm::vec3(static_cast<float>(std::round(x / step) * step), static_cast<float>(std::round(y / step) * step), 0.0f);
}

TEST(HapticGripMotion, ASlowPushReadThroughAnEncoderIsQuietWithTheResolution) {
  // 12 mm/s along x through 0.04 mm counts, y at rest on a count boundary's edge: the fixed span
  // jitters by a count over 4 ms (10 mm/s); fitted within the resolution the velocity is quiet.
  constexpr double kStep = 4e-5, kSpeed = 0.012;
  GripMotion fixed, fitted(kStep);
  double worst_fixed = 0.0, worst_fitted = 0.0, worst_y = 0.0;
  for (int i = 0; i < 600; ++i) {
    const double t = 0.001 * i;
    const glm::vec3 p = quantised(kSpeed * t, 0.5 * kStep + 1e-6 * std::sin(900.0 * t), kStep);
    const glm::vec3 a = fixed.update(p, 0.001), b = fitted.update(p, 0.001);
    if (i < 200) continue;  // past the longest window
    worst_fixed = std::max(worst_fixed, std::fabs(a.x - kSpeed));
    worst_fitted = std::max(worst_fitted, std::fabs(b.x - kSpeed));
    worst_y = std::max(worst_y, static_cast<double>(std::fabs(b.y)));
    EXPECT_EQ(fitted.window().x, kGripVelocityMaxSpan) << i;
  }
  EXPECT_GT(worst_fixed, 0.005);   // the fixed span: a count in 4 ms
  EXPECT_LT(worst_fitted, 0.001);  // about a count over the 80 ms window
  EXPECT_LT(worst_y, 0.001);       // the axis at rest, flipping between two counts
}

TEST(HapticGripMotion, WithTheResolutionAStopStillShowsWithinAFewPeriods) {
  // 0.1 m/s through 0.04 mm counts, then a dead stop: the window shrinks as soon as the readings
  // leave the line, so the estimate falls below a tenth of the speed within 10 periods, not 80.
  constexpr double kStep = 4e-5;
  GripMotion m(kStep);
  double x = 0.0;
  for (int i = 0; i < 200; ++i) m.update(quantised(x += 1e-4, 0.0, kStep), 0.001);
  int periods = 0;
  glm::vec3 v(1.0f);
  while (v.x > 0.01f && periods < 100) {
    v = m.update(quantised(x, 0.0, kStep), 0.001);
    ++periods;
  }
  EXPECT_LE(periods, 10);
}

TEST(HapticGripMotion, AResolutionThatIsNotANumberOfMetresIsRefused) {
  EXPECT_THROW(GripMotion(-1e-5), InvalidArgument);
  EXPECT_THROW(GripMotion(NAN), InvalidArgument);
}

}  // namespace
}  // namespace hf::haptics
