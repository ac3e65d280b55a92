// SPDX-License-Identifier: GPL-3.0-or-later
// Falcon kinematics: inverse then forward over the workspace, Jacobian against finite
// differences, virtual work, encoder scale, command scaling and clamping.
#include <gtest/gtest.h>

#include <cmath>

#include "haptics/falcon/falcon_kinematics.h"

using namespace hf::haptics::falcon;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::vector<glm::dvec3> workspaceGrid(double half, int n) {
  std::vector<glm::dvec3> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double s = 2.0 * half / (n - 1);
        points.emplace_back(-half + i * s, -half + j * s, -half + k * s);
      }
  return points;
}

}  // namespace

TEST(FalconKinematics, EncoderScaleMatchesTheGearing) {
  // 1280 counts per motor turn, gear 110/14.25: 0.036434 degrees of arm per count, 35 deg at 0.
  EXPECT_NEAR(FalconKinematics::angleFromCount(0) * 180.0 / kPi, 35.0, 1e-12);
  EXPECT_NEAR((FalconKinematics::angleFromCount(1000) - FalconKinematics::angleFromCount(0)) * 180.0 / kPi,
              1000 * 360.0 / (1280.0 * 110.0 / 14.25), 1e-9);
  EXPECT_NEAR(360.0 / (1280.0 * kGearRatio), 0.036434, 1e-6);
  for (int c : {-32768, -1234, -1, 0, 1, 999, 32767})
    EXPECT_EQ(FalconKinematics::countFromAngle(FalconKinematics::angleFromCount(static_cast<std::int16_t>(c))), c);
  EXPECT_FALSE(FalconKinematics::countFromAngle(35.0 * kPi / 180.0 + 33000 * 2 * kPi / (1280 * kGearRatio)));
  EXPECT_FALSE(FalconKinematics::countFromAngle(std::nan("")));
}

TEST(FalconKinematics, InverseMatchesTheHalfAngleSolution) {
  // Upper-arm angles (rad) from libnifalcon's published equations (the half-angle quadratic,
  // minus root), evaluated separately; kinematic z = device z + 0.12 m.
  const FalconKinematics kin;
  struct Case {
    glm::dvec3 device_m;
    glm::dvec3 angles;
  };
  const Case cases[] = {
      {{0.0, 0.0, 0.08 - kWorkspaceCentreZ}, {-0.20594969, -0.20594969, -0.20594969}},
      {{0.02, -0.01, 0.15 - kWorkspaceCentreZ}, {1.00038138, 0.64964842, 0.92340765}},
      {{0.03, 0.03, 0.10 - kWorkspaceCentreZ}, {0.0292624278, 0.000382509106, 0.777502591}},
  };
  for (const Case& c : cases) {
    const auto a = kin.inverse(c.device_m);
    ASSERT_TRUE(a);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR((*a)[i], c.angles[i], 1e-7) << "arm " << i;
  }
}

TEST(FalconKinematics, SymmetricPosesGiveEqualArmAngles) {
  const FalconKinematics kin;
  for (double z : {-0.04, 0.0, 0.04}) {
    const auto a = kin.inverse({0.0, 0.0, z});
    ASSERT_TRUE(a) << z;
    EXPECT_NEAR(a->x, a->y, 1e-12);
    EXPECT_NEAR(a->y, a->z, 1e-12);
  }
  // Pulling the grip out (+z) turns every upper arm the same way.
  EXPECT_GT(kin.inverse({0, 0, 0.04})->x, kin.inverse({0, 0, 0.0})->x);
}

TEST(FalconKinematics, InverseThenForwardIsIdentityOverTheWorkspace) {
  const FalconKinematics kin;
  int worst_iterations = 0;
  double worst_error = 0.0;
  for (const glm::dvec3& p : workspaceGrid(kWorkspaceHalfEdge, 9)) {
    const auto angles = kin.inverse(p);
    ASSERT_TRUE(angles) << "unreachable (" << p.x << ", " << p.y << ", " << p.z << ")";
    const ForwardResult fk = kin.forward(*angles, glm::dvec3(0.0));  // cold start at the centre
    ASSERT_TRUE(fk.converged) << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    worst_error = std::max(worst_error, glm::length(fk.position_m - p));
    worst_iterations = std::max(worst_iterations, fk.iterations);
  }
  EXPECT_LT(worst_error, 1e-9);
  EXPECT_LE(worst_iterations, 15);
}

TEST(FalconKinematics, EncoderRoundTripIsWithinQuantisation) {
  const FalconKinematics kin;
  glm::dvec3 guess(0.0);
  double worst = 0.0;
  for (const glm::dvec3& p : workspaceGrid(0.035, 7)) {
    const auto counts = kin.countsFor(p);
    ASSERT_TRUE(counts);
    const ForwardResult fk = kin.forward(FalconKinematics::anglesFromCounts(*counts), guess);
    ASSERT_TRUE(fk.converged);
    guess = fk.position_m;  // warm start, as the device does
    worst = std::max(worst, glm::length(fk.position_m - p));
  }
  // Half a count is 0.018 deg; with arm lever arms ~0.1 m that is well under 0.3 mm.
  EXPECT_LT(worst, 3e-4);
  EXPECT_GT(worst, 1e-7);  // quantisation is there at all
}

TEST(FalconKinematics, PositionResolutionBoundsTheQuantisationSpreadPerAxis) {
  // The spread (largest less smallest error) of the quantised readings per axis, over a fine grid
  // of the cube, stays within positionResolutionM(), and is not far below it (a useful bound).
  const FalconKinematics kin;
  const double resolution = kin.positionResolutionM();
  EXPECT_GT(resolution, 2e-5);
  EXPECT_LT(resolution, 3e-4);
  glm::dvec3 guess(0.0);
  double worst_spread = 0.0;
  for (const glm::dvec3& centre : workspaceGrid(0.036, 5)) {
    // Readings about one pose: their error spread per axis.
    glm::dvec3 lo(1.0), hi(-1.0);
    for (int i = 0; i < 400; ++i) {
      const glm::dvec3 p = centre + 1e-4 * glm::dvec3(std::sin(0.37 * i), std::cos(0.53 * i), std::sin(0.71 * i + 1.0));
      const auto counts = kin.countsFor(p);
      ASSERT_TRUE(counts);
      const ForwardResult fk = kin.forward(FalconKinematics::anglesFromCounts(*counts), guess);
      ASSERT_TRUE(fk.converged);
      guess = fk.position_m;
      lo = glm::min(lo, fk.position_m - p);
      hi = glm::max(hi, fk.position_m - p);
    }
    for (int a = 0; a < 3; ++a) worst_spread = std::max(worst_spread, hi[a] - lo[a]);
  }
  EXPECT_LE(worst_spread, resolution);
  EXPECT_GT(worst_spread, 0.3 * resolution);
}

TEST(FalconKinematics, JacobianMatchesFiniteDifferences) {
  const FalconKinematics kin;
  const double h = 1e-6;
  for (const glm::dvec3& p : workspaceGrid(0.035, 5)) {
    const auto jinv = kin.inverseJacobian(p);
    const auto j = kin.jacobian(p);
    ASSERT_TRUE(jinv && j);
    for (int axis = 0; axis < 3; ++axis) {
      glm::dvec3 dp(0.0);
      dp[axis] = h;
      const glm::dvec3 fd = (*kin.inverse(p + dp) - *kin.inverse(p - dp)) / (2.0 * h);
      for (int arm = 0; arm < 3; ++arm) EXPECT_NEAR((*jinv)[axis][arm], fd[arm], 1e-5 * (1.0 + std::abs(fd[arm])));
    }
    const glm::dmat3 identity = (*j) * (*jinv);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) EXPECT_NEAR(identity[c][r], c == r ? 1.0 : 0.0, 1e-9);
  }
}

TEST(FalconKinematics, TorqueDoesTheSameVirtualWorkAsTheForce) {
  const FalconKinematics kin;
  const glm::dvec3 p(0.01, -0.02, 0.015);
  const glm::dvec3 force(1.5, -2.0, 3.0);
  const glm::dvec3 torque = glm::transpose(*kin.jacobian(p)) * force;
  const glm::dvec3 dp(2e-7, 1e-7, -3e-7);
  const glm::dvec3 dtheta = *kin.inverse(p + dp) - *kin.inverse(p);
  EXPECT_NEAR(glm::dot(torque, dtheta), glm::dot(force, dp), 1e-3 * std::abs(glm::dot(force, dp)));
  // And back: the force a torque makes is the one asked for.
  const glm::dvec3 f_back = glm::transpose(*kin.inverseJacobian(p)) * torque;
  EXPECT_NEAR(glm::length(f_back - force), 0.0, 1e-9);
}

TEST(FalconKinematics, CommandsScaleTogetherAndClampToInt16) {
  const MotorCommand small = FalconKinematics::commandFor({0.1, -0.2, 0.05});
  EXPECT_FALSE(small.clamped);
  EXPECT_EQ(small.value[0], -1000);  // x10,000, negated
  EXPECT_EQ(small.value[1], 2000);
  EXPECT_EQ(small.value[2], -500);
  const glm::dvec3 back = FalconKinematics::torqueFromCommand(small.value);
  EXPECT_NEAR(back.y, -0.2, 1e-12);

  const MotorCommand big = FalconKinematics::commandFor({10.0, -5.0, 2.5});  // 100,000 does not fit
  EXPECT_TRUE(big.clamped);
  EXPECT_EQ(big.value[0], -32767);
  EXPECT_NEAR(big.value[1], 32767 / 2.0, 1.0);   // direction kept
  EXPECT_NEAR(big.value[2], -32767 / 4.0, 1.0);
  const MotorCommand nan = FalconKinematics::commandFor({std::nan(""), 0.0, 0.0});
  EXPECT_TRUE(nan.clamped);
  EXPECT_EQ(nan.value, (std::array<std::int16_t, 3>{0, 0, 0}));
}

TEST(FalconKinematics, OutOfReachIsReportedNotComputed) {
  const FalconKinematics kin;
  EXPECT_FALSE(kin.inverse({0.0, 0.0, 0.2}));
  EXPECT_FALSE(kin.inverse({std::nan(""), 0.0, 0.0}));
  EXPECT_FALSE(kin.jacobian({0.0, 0.0, 0.2}));
  // Angles no pose has: the iteration stops within its bound and says so.
  const ForwardResult fk = kin.forward({3.0, -3.0, 0.0}, glm::dvec3(0.0), 15);
  EXPECT_FALSE(fk.converged);
  EXPECT_LE(fk.iterations, 15);
  EXPECT_TRUE(std::isfinite(fk.position_m.x) && std::isfinite(fk.position_m.y) && std::isfinite(fk.position_m.z));
}
