// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/probe_checks.h"

#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"
#include "common/format.h"
#include "fluid/validate.h"

namespace hf::obstacle {

void validateMotion(const glm::vec3& velocity_m_s, const glm::vec3& angular_velocity_rad_s) {
  if (!allFinite(velocity_m_s) || !allFinite(angular_velocity_rad_s)) {
    throw InvalidArgument("probe motion must be finite: velocity " + vecText(velocity_m_s) +
                          " m/s, angular velocity " + vecText(angular_velocity_rad_s) + " rad/s");
  }
  if (glm::length(velocity_m_s) > fluid::kMaxProbeSpeed) {
    throw InvalidArgument("probe speed must be at most " + num(fluid::kMaxProbeSpeed) + " m/s, got " +
                          vecText(velocity_m_s) + " m/s");
  }
  if (glm::length(angular_velocity_rad_s) > fluid::kMaxProbeSpin) {
    throw InvalidArgument("probe angular speed must be at most " + num(fluid::kMaxProbeSpin) + " rad/s, got " +
                          vecText(angular_velocity_rad_s) + " rad/s");
  }
}

void validatePose(const SpherePose& p, const fluid::Grid& g) {
  if (!allFinite(p.centre_m)) {
    throw InvalidArgument("probe pose must be finite: centre " + vecText(p.centre_m) + " m");
  }
  validateMotion(p.velocity_m_s, p.angular_velocity_rad_s);
  if (!std::isfinite(p.radius_m) || p.radius_m < g.cell_size_m) {
    throw InvalidArgument("probe radius must be at least one cell (" + num(g.cell_size_m) +
                          " m) to be seen by the grid, got " + num(p.radius_m) + " m; raise the radius or the resolution");
  }
  const glm::vec3 lo = g.origin_m + g.cell_size_m, hi = g.origin_m + g.sizeM() - g.cell_size_m;
  const std::string what = "probe sphere (centre " + vecText(p.centre_m) + " m, radius " + num(p.radius_m) +
                           " m) is not inside the domain with at least one cell (" + num(g.cell_size_m) +
                           " m) of fluid between it and every wall";
  if (glm::any(glm::greaterThan(lo + p.radius_m, hi - p.radius_m))) {
    throw InvalidArgument(what + "; with this radius it cannot fit: the radius must be at most " +
                          num(0.5f * glm::min(glm::min(g.sizeM().x, g.sizeM().y), g.sizeM().z) - g.cell_size_m) + " m");
  }
  if (glm::any(glm::lessThan(p.centre_m - p.radius_m, lo)) || glm::any(glm::greaterThan(p.centre_m + p.radius_m, hi))) {
    throw InvalidArgument(what + "; its centre must stay within " + vecText(lo + p.radius_m) + " .. " +
                          vecText(hi - p.radius_m) + " m");
  }
}

void validatePose(const MeshExtent& extent, const RigidPose& p, const fluid::Grid& g) {
  validateTransform(p.transform);
  validateMotion(p.velocity_m_s, p.angular_velocity_rad_s);
  const double visits = columnVisitBound(extent, p.transform, g.cell_size_m);
  if (!(visits <= kMaxColumnVisits)) {
    throw InvalidArgument("the posed mesh's triangles could cover up to " + num(visits) +
                          " cell columns per step (limit " + num(kMaxColumnVisits) +
                          "); split its large triangles, scale it down or use a coarser grid");
  }
  const WorldBox box = worldBox(extent, p.transform);
  const glm::vec3 lo = g.origin_m + g.cell_size_m, hi = g.origin_m + g.sizeM() - g.cell_size_m;
  if (glm::any(glm::lessThan(box.lo, lo)) || glm::any(glm::greaterThan(box.hi, hi))) {
    throw InvalidArgument("the posed mesh (bounds " + vecText(box.lo) + " .. " + vecText(box.hi) +
                          " m) is not inside the domain with at least one cell (" + num(g.cell_size_m) +
                          " m) of fluid between it and every wall: keep it within " + vecText(lo) + " .. " +
                          vecText(hi) + " m (move it, scale it down, or enlarge the domain)");
  }
}

}  // namespace hf::obstacle
