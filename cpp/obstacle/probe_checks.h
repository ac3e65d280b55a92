// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Checks of a probe's pose and motion in a grid; each throws hf::InvalidArgument saying what to
// change. The body must keep at least one whole fluid cell between itself and every wall, so the
// faces summed into its force enclose it and the force does not depend on the pressure's
// arbitrary constant. Speed limits: fluid/validate.h.
#include <glm/glm.hpp>

#include "fluid/grid.h"
#include "obstacle/sphere_probe.h"
#include "obstacle/triangle_mesh.h"

namespace hf::obstacle {

// Finite, and within kMaxProbeSpeed (m/s) and kMaxProbeSpin (rad/s).
void validateMotion(const glm::vec3& velocity_m_s, const glm::vec3& angular_velocity_rad_s);
// A sphere: finite centre, a radius of at least one cell, inside the domain with the margin.
void validatePose(const SpherePose& pose, const fluid::Grid& grid);
// A posed mesh: a usable transform, a bounded voxelization cost, and its conservative world box
// (obstacle::worldBox) inside the domain with the margin.
void validatePose(const MeshExtent& extent, const RigidPose& pose, const fluid::Grid& grid);

}  // namespace hf::obstacle
