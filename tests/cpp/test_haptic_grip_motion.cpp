// SPDX-License-Identifier: GPL-3.0-or-later
// GripMotion: the velocity the passivity controller acts on, from the positions the loop reads.
#include <gtest/gtest.h>

#include <cmath>

#include "haptics/grip_motion.h"

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

}  // namespace
}  // namespace hf::haptics
