// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Checks of the grid a simulation is made on, and of a time step on it (beside the settings
// checks of fluid/validate.h, whose ranges they use); each throws hf::InvalidArgument saying
// what to change.
#include <glm/glm.hpp>

#include "fluid/fluid_params.h"
#include "fluid/grid.h"
#include "compute/device.h"

namespace hf::fluid {

// Enough cells on every axis for the stencils and walls (the message gives the minimum).
void checkResolution(const glm::ivec3& resolution);
// The grid of `resolution` cells over a box of `domain_size_m` (m) whose minimum corner is at
// `origin_m` (m): both finite, the origin within kMaxOriginOffset, cells cubic and of an edge
// within kMinCellSize .. kMaxCellSize.
Grid makeGrid(const glm::ivec3& resolution, const glm::vec3& domain_size_m, const glm::vec3& origin_m);
// The grid's fields fit the device: its largest 3D texture and a share of its memory.
void checkFits(const Grid& grid, const compute::DeviceInfo& info);
// A time step `dt_s` (s) within kMinTimeStep .. kMaxTimeStep whose derived scales with these
// settings on this grid (rho h / dt, dt / (rho h)) are normal floats. In double, so a value
// float cannot hold (1e-40, 1e300) is reported as given.
void validateStep(double dt_s, const FluidParams& params, const Grid& grid);
// The smallest relative residual float32 pressure can reach on this grid: the rounding of
// p - p_nb against the rhs grows with the pressure's range, about linearly in the cells per
// axis. Measured (multigrid, moving sphere, closed and open box, 16^3-64^3): the lowest residual
// reached was 0.07-0.13 x FLT_EPSILON x n, a cold start's floor 0.3-0.55 x; this returns the
// lowest, FLT_EPSILON x n / 16, so only tolerances that can never be met are refused.
float pressureToleranceFloor(const Grid& grid);
// A pressure_tolerance of 0 (fixed count) or at least pressureToleranceFloor(grid); the message
// names the floor.
void checkPressureTolerance(const FluidParams& params, const Grid& grid);

}  // namespace hf::fluid
