// SPDX-License-Identifier: GPL-3.0-or-later
// Orientation through the haptics layer: the workspace map's mirror of a rotation and of an
// angular velocity, and the host device's spin estimate from pushed quaternions.
#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "common/error.h"
#include "haptics/devices/host_device.h"
#include "haptics/rendering/workspace_map.h"

namespace hf::haptics {
namespace {

void expectNear(const glm::mat3& a, const glm::mat3& b, float tol) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(a[c][r], b[c][r], tol) << "column " << c << " row " << r;
}

TEST(HapticOrientation, TheWorkspaceMapMirrorsRotationsAndSpins) {
  const glm::quat q = glm::angleAxis(0.7f, glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f)));
  const glm::vec3 w(0.4f, -1.2f, 2.0f);
  for (const glm::vec3 scale : {glm::vec3(2.0f), glm::vec3(-3.0f, 1.0f, 1.0f), glm::vec3(1.0f, -1.0f, -0.5f),
                                glm::vec3(-1.0f, -2.0f, -3.0f)}) {
    WorkspaceMap map;
    map.scale = scale;
    const glm::mat3 s(glm::vec3(glm::sign(scale.x), 0, 0), glm::vec3(0, glm::sign(scale.y), 0),
                      glm::vec3(0, 0, glm::sign(scale.z)));
    // A rotation seen through the mirror S: S R S (still a rotation).
    expectNear(glm::mat3_cast(map.orientationToDomain(q)), s * glm::mat3_cast(q) * s, 1e-6f);
    // An angular velocity is a pseudovector: det(S) S w. Check it against the rotation it makes.
    const glm::vec3 mapped = map.angularVelocityToDomain(w);
    const float det = glm::determinant(s);
    EXPECT_NEAR(glm::length(mapped - det * (s * w)), 0.0f, 1e-6f);
    const glm::quat turn = glm::angleAxis(0.01f * glm::length(w), glm::normalize(w));
    const glm::quat mapped_turn = glm::angleAxis(0.01f * glm::length(mapped), glm::normalize(mapped));
    expectNear(glm::mat3_cast(mapped_turn), s * glm::mat3_cast(turn) * s, 1e-6f);
  }
}

TEST(HapticOrientation, HostDeviceSpinFromPushes) {
  HostDevice d(5.0f, false);
  EXPECT_FALSE(d.stateAfter(0.0).has_orientation);
  const glm::vec3 axis = glm::normalize(glm::vec3(1.0f, 2.0f, -2.0f));
  d.pushPose(glm::vec3(0.0f), glm::angleAxis(0.3f, axis), 1.0);
  d.pushPose(glm::vec3(0.0f), glm::angleAxis(0.5f, axis), 1.1);
  const DeviceState s = d.stateAfter(0.05);  // no extrapolation: the pushed rotation
  ASSERT_TRUE(s.has_orientation);
  EXPECT_NEAR(glm::length(s.angular_velocity_rad_s - axis * 2.0f), 0.0f, 1e-4f);  // 0.2 rad in 0.1 s
  expectNear(glm::mat3_cast(s.orientation), glm::mat3_cast(glm::angleAxis(0.5f, axis)), 1e-6f);
  EXPECT_THROW(d.pushPose(glm::vec3(0.0f), glm::quat(0.0f, 0.0f, 0.0f, 0.0f), 1.2), InvalidArgument);
}

}  // namespace
}  // namespace hf::haptics
