// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/falcon_kinematics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hf::haptics::falcon {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadPerCount = 2.0 * kPi / (kCountsPerMotorTurn * kGearRatio);
constexpr double kAngleAtZero = kAngleAtZeroCountDeg * kPi / 180.0;
constexpr double kMaxNewtonStep = 0.02;  // m, keeps an early Newton step inside the workspace

struct ArmAngles {
  double t1, t2, t3;
};

double wrap(double angle) {
  while (angle > kPi) angle -= 2.0 * kPi;
  while (angle <= -kPi) angle += 2.0 * kPi;
  return angle;
}

}  // namespace

glm::dmat3 matrixFromRows(const glm::dvec3& r0, const glm::dvec3& r1, const glm::dvec3& r2) {
  return glm::transpose(glm::dmat3(r0, r1, r2));
}

FalconKinematics::FalconKinematics(FalconGeometry geometry) : g_(geometry) {
  for (std::size_t i = 0; i < 3; ++i) {
    cos_phi_[i] = std::cos(g_.phi_deg[i] * kPi / 180.0);
    sin_phi_[i] = std::sin(g_.phi_deg[i] * kPi / 180.0);
  }
}

namespace {

// All three angles of one arm for a point in its arm frame; false out of reach.
bool solveArm(const FalconGeometry& g, const glm::dvec3& q, ArmAngles& out) {
  const double cos_t3 = (q.y + g.f) / g.b;
  if (!(std::abs(cos_t3) <= 1.0)) return false;
  out.t3 = std::acos(cos_t3);
  const double rho = g.d + g.e + g.b * std::sin(out.t3);
  // |(X, z) - a u(t1)| = rho with X = x + c  ->  A cos t1 + B sin t1 = C
  const double X = q.x + g.c;
  const double A = 2.0 * g.a * X;
  const double B = 2.0 * g.a * q.z;
  const double C = X * X + q.z * q.z + g.a * g.a - rho * rho;
  const double R = std::hypot(A, B);
  if (!(R > 0.0) || !(std::abs(C) <= R)) return false;
  out.t1 = wrap(std::atan2(B, A) - std::acos(C / R));
  out.t2 = std::atan2(q.z - g.a * std::sin(out.t1), X - g.a * std::cos(out.t1));
  return true;
}

}  // namespace

std::optional<glm::dvec3> FalconKinematics::inverse(const glm::dvec3& position_m) const {
  if (!std::isfinite(position_m.x) || !std::isfinite(position_m.y) || !std::isfinite(position_m.z)) return std::nullopt;
  const glm::dvec3 p = position_m + glm::dvec3(0.0, 0.0, kWorkspaceCentreZ);
  glm::dvec3 angles;
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 q(cos_phi_[i] * p.x + sin_phi_[i] * p.y - g_.r, -sin_phi_[i] * p.x + cos_phi_[i] * p.y - g_.s, p.z);
    ArmAngles arm{};
    if (!solveArm(g_, q, arm)) return std::nullopt;
    angles[i] = arm.t1;
  }
  return angles;
}

std::optional<glm::dmat3> FalconKinematics::inverseJacobian(const glm::dvec3& position_m) const {
  const glm::dvec3 p = position_m + glm::dvec3(0.0, 0.0, kWorkspaceCentreZ);
  glm::dvec3 rows[3];
  for (int i = 0; i < 3; ++i) {
    const double cp = cos_phi_[i], sp = sin_phi_[i];
    const glm::dvec3 q(cp * p.x + sp * p.y - g_.r, -sp * p.x + cp * p.y - g_.s, p.z);
    ArmAngles arm{};
    if (!solveArm(g_, q, arm)) return std::nullopt;
    const double rho = g_.d + g_.e + g_.b * std::sin(arm.t3);
    const double s1 = std::sin(arm.t1), c1 = std::cos(arm.t1);
    const double s2 = std::sin(arm.t2), c2 = std::cos(arm.t2);
    const double s3 = std::sin(arm.t3), c3 = std::cos(arm.t3);
    // Columns d q / d(t1, t2, t3) of the closure equations.
    const glm::dvec3 dq_dt1(-g_.a * s1, 0.0, g_.a * c1);
    const glm::dvec3 dq_dt2(-rho * s2, 0.0, rho * c2);
    const glm::dvec3 dq_dt3(g_.b * c3 * c2, -g_.b * s3, g_.b * c3 * s2);
    const glm::dmat3 M(dq_dt1, dq_dt2, dq_dt3);
    const double det = glm::determinant(M);
    if (!(std::abs(det) > 1e-12)) return std::nullopt;
    const glm::dmat3 Minv = glm::inverse(M);
    // Row 0 of M^-1: d t1 / d q; then d q / d p = Rz(-phi).
    const glm::dvec3 dt1_dq(Minv[0][0], Minv[1][0], Minv[2][0]);
    rows[i] = glm::dvec3(dt1_dq.x * cp - dt1_dq.y * sp, dt1_dq.x * sp + dt1_dq.y * cp, dt1_dq.z);
  }
  return matrixFromRows(rows[0], rows[1], rows[2]);
}

std::optional<glm::dmat3> FalconKinematics::jacobian(const glm::dvec3& position_m) const {
  const auto inv = inverseJacobian(position_m);
  if (!inv) return std::nullopt;
  const double det = glm::determinant(*inv);
  if (!std::isfinite(det) || std::abs(det) < 1e-9) return std::nullopt;
  return glm::inverse(*inv);
}

double FalconKinematics::positionResolutionM() const {
  constexpr int kSteps = 8;  // 9 points per edge
  double worst = 0.0;
  for (int i = 0; i <= kSteps; ++i) {
    for (int j = 0; j <= kSteps; ++j) {
      for (int k = 0; k <= kSteps; ++k) {
        const glm::dvec3 p = glm::dvec3(-kWorkspaceHalfEdge) +
                             (2.0 * kWorkspaceHalfEdge / kSteps) * glm::dvec3(i, j, k);
        const auto jac = jacobian(p);  // columns: motors; rows: axes
        if (!jac) continue;
        for (int axis = 0; axis < 3; ++axis) {
          double spread = 0.0;
          for (int motor = 0; motor < 3; ++motor) spread += std::abs((*jac)[motor][axis]) * kRadPerCount;
          worst = std::max(worst, spread);
        }
      }
    }
  }
  return worst;
}

ForwardResult FalconKinematics::forward(const glm::dvec3& angles_rad, const glm::dvec3& guess_m, int max_iterations,
                                        double tolerance_rad) const {
  ForwardResult result;
  result.position_m = inverse(guess_m) ? guess_m : glm::dvec3(0.0);
  for (int it = 0; it < max_iterations; ++it) {
    const auto angles = inverse(result.position_m);
    const auto jinv = inverseJacobian(result.position_m);
    if (!angles || !jinv) return result;
    const glm::dvec3 err(wrap(angles_rad.x - angles->x), wrap(angles_rad.y - angles->y), wrap(angles_rad.z - angles->z));
    const double worst = std::max({std::abs(err.x), std::abs(err.y), std::abs(err.z)});
    if (!std::isfinite(worst)) return result;
    if (worst < tolerance_rad) {
      result.converged = true;
      return result;
    }
    const double det = glm::determinant(*jinv);
    if (!(std::abs(det) > 1e-9)) return result;
    glm::dvec3 step = glm::inverse(*jinv) * err;
    const double len = glm::length(step);
    if (len > kMaxNewtonStep) step *= kMaxNewtonStep / len;
    // Halve a step that leaves the reachable set.
    int halvings = 0;
    while (!inverse(result.position_m + step) && halvings < 20) {
      step *= 0.5;
      ++halvings;
    }
    result.position_m += step;
    result.iterations = it + 1;
  }
  const auto angles = inverse(result.position_m);
  if (angles) {
    const glm::dvec3 err = angles_rad - *angles;
    result.converged = std::max({std::abs(wrap(err.x)), std::abs(wrap(err.y)), std::abs(wrap(err.z))}) < tolerance_rad;
  }
  return result;
}

double FalconKinematics::angleFromCount(std::int16_t count) { return kAngleAtZero + count * kRadPerCount; }

std::optional<std::int16_t> FalconKinematics::countFromAngle(double angle_rad) {
  const double counts = std::round((angle_rad - kAngleAtZero) / kRadPerCount);
  if (!(counts >= std::numeric_limits<std::int16_t>::min() && counts <= std::numeric_limits<std::int16_t>::max()))
    return std::nullopt;
  return static_cast<std::int16_t>(counts);
}

glm::dvec3 FalconKinematics::anglesFromCounts(const std::array<std::int16_t, 3>& counts) {
  return {angleFromCount(counts[0]), angleFromCount(counts[1]), angleFromCount(counts[2])};
}

std::optional<std::array<std::int16_t, 3>> FalconKinematics::countsFor(const glm::dvec3& position_m) const {
  const auto angles = inverse(position_m);
  if (!angles) return std::nullopt;
  std::array<std::int16_t, 3> counts{};
  for (int i = 0; i < 3; ++i) {
    const auto c = countFromAngle((*angles)[i]);
    if (!c) return std::nullopt;
    counts[static_cast<std::size_t>(i)] = *c;
  }
  return counts;
}

MotorCommand FalconKinematics::commandFor(const glm::dvec3& torque_nm) {
  MotorCommand out;
  glm::dvec3 raw = -kCommandPerNewtonMetre * torque_nm;
  if (!std::isfinite(raw.x) || !std::isfinite(raw.y) || !std::isfinite(raw.z)) {
    out.clamped = true;  // nothing sensible to send: zero
    return out;
  }
  const double limit = std::numeric_limits<std::int16_t>::max();
  const double worst = std::max({std::abs(raw.x), std::abs(raw.y), std::abs(raw.z)});
  if (worst > limit) {
    raw *= limit / worst;
    out.clamped = true;
  }
  for (int i = 0; i < 3; ++i)
    out.value[static_cast<std::size_t>(i)] =
        static_cast<std::int16_t>(std::clamp(std::round(raw[i]), -limit, limit));
  return out;
}

glm::dvec3 FalconKinematics::torqueFromCommand(const std::array<std::int16_t, 3>& command) {
  return glm::dvec3(command[0], command[1], command[2]) / -kCommandPerNewtonMetre;
}

}  // namespace hf::haptics::falcon
