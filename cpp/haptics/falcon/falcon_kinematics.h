// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Kinematics of the Novint Falcon (pure math, no I/O): Stamper's parallel delta with the
// libnifalcon parameters. Positions are in the device frame (m): the kinematic frame shifted so
// the workspace centre (0, 0, kWorkspaceCentreZ) is the origin. Angles are in radians.
//
// Per arm i (rotated by phi_i about z), in the arm frame q = Rz(-phi_i) p - (r, s, 0):
//   q.x + c = a cos t1 + rho cos t2
//   q.z     = a sin t1 + rho sin t2                    rho = d + e + b sin t3
//   q.y     = b cos t3 - f
// t1 is the motor-driven upper arm, t2 the parallelogram's in-plane direction, t3 its
// out-of-plane angle. Inverse: t3 from an arccos, t1 from 2a(q.x + c) cos t1 + 2a q.z sin t1 =
// (q.x + c)^2 + q.z^2 + a^2 - rho^2 (the root libnifalcon takes as the minus root of the
// half-angle quadratic), t2 from the remaining vector. Forward: Newton, bounded iterations.
//
// "Jacobian" here is the forward one, J = dp/dt1 (m/rad, column i = motor i), the inverse of the
// stacked rows d(t1_i)/dp. By virtual work the motor torques for a force F are tau = J^T F, and a
// torque tau makes the force F = J^-T tau.
#include <array>
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

namespace hf::haptics::falcon {

struct FalconGeometry {
  double a = 0.060;      // m, upper arm
  double b = 0.1025;     // m, parallelogram link
  double c = 0.01443;    // m, offset of the arm frame along its x
  double d = 0.01125;    // m, link hinge offsets (top, bottom)
  double e = 0.01125;
  double f = -0.025;     // m, effector offset along the motor axis
  double r = 0.040;      // m, motor axis offset from the centre (radial)
  double s = -0.02309;   // m, motor axis offset along the axis
  std::array<double, 3> phi_deg{105.0, -15.0, -135.0};  // arm directions about z
};

// Encoder counts <-> upper-arm angle: 320 slots x 4 = 1280 counts per motor turn, capstan gear
// 110 / 14.25, 35 degrees at count 0.
constexpr double kCountsPerMotorTurn = 1280.0;
constexpr double kGearRatio = 110.0 / 14.25;
constexpr double kAngleAtZeroCountDeg = 35.0;
constexpr double kWorkspaceCentreZ = 0.120;  // m, kinematic frame; the +-0.04 m cube around it is reachable
constexpr double kWorkspaceHalfEdge = 0.040; // m
// Motor command per N m of arm torque. libnifalcon scales by 10,000 and negates; the physical unit
// of a command is undocumented, so force magnitudes on real hardware need calibrating.
constexpr double kCommandPerNewtonMetre = 10000.0;

struct MotorCommand {
  std::array<std::int16_t, 3> value{};
  bool clamped = false;  // the torques did not fit int16: all three were scaled down together
};

struct ForwardResult {
  glm::dvec3 position_m{0.0};
  int iterations = 0;
  bool converged = false;
};

class FalconKinematics {
 public:
  explicit FalconKinematics(FalconGeometry geometry = {});

  // Upper-arm angles t1 for each arm (rad); nullopt when the point is out of reach.
  std::optional<glm::dvec3> inverse(const glm::dvec3& position_m) const;
  // Newton iteration from `guess` (the last pose) towards the pose with these angles.
  ForwardResult forward(const glm::dvec3& angles_rad, const glm::dvec3& guess_m = glm::dvec3(0.0),
                        int max_iterations = 15, double tolerance_rad = 1e-10) const;
  // Rows d(t1_i)/dp (rad/m); nullopt out of reach or at a singular pose.
  std::optional<glm::dmat3> inverseJacobian(const glm::dvec3& position_m) const;
  // dp/dt1 (m/rad), the inverse of inverseJacobian().
  std::optional<glm::dmat3> jacobian(const glm::dvec3& position_m) const;

  // The most one axis' reading moves across one count of every encoder, anywhere in the reachable
  // cube about the workspace centre (m): the spread of the quantization error of a position reading (sum over the motors of
  // |dp_axis/dt1_i| x one count, the largest over a 9^3 grid of the cube and the three axes).
  double positionResolutionM() const;

  // Encoder counts <-> angles.
  static double angleFromCount(std::int16_t count);
  static std::optional<std::int16_t> countFromAngle(double angle_rad);
  static glm::dvec3 anglesFromCounts(const std::array<std::int16_t, 3>& counts);
  std::optional<std::array<std::int16_t, 3>> countsFor(const glm::dvec3& position_m) const;

  // Motor torques (N m) <-> commands, scaled together so the direction is kept.
  static MotorCommand commandFor(const glm::dvec3& torque_nm);
  static glm::dvec3 torqueFromCommand(const std::array<std::int16_t, 3>& command);

  const FalconGeometry& geometry() const { return g_; }

 private:
  FalconGeometry g_;
  std::array<double, 3> cos_phi_{};
  std::array<double, 3> sin_phi_{};
};

// Column-major glm matrices from three rows.
glm::dmat3 matrixFromRows(const glm::dvec3& r0, const glm::dvec3& r1, const glm::dvec3& r2);

}  // namespace hf::haptics::falcon
