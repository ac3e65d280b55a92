// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/pressure_jacobi.h"


#include <algorithm>

#include "compute/workgroup.h"

namespace hf::fluid {

PressureJacobi::PressureJacobi(const Grid& grid) : grid_(grid), sweep_("jacobi.comp", compute::cellGroupDefines()) {
  sweep_.set("u_res", grid.res);
}

void PressureJacobi::sweeps(FluidFields& f, int count) {
  f.rhs.bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  f.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  for (int i = 0; i < count; ++i) {
    f.pressure.cur().bindImage(1, compute::Access::Read);
    f.pressure.next().bindImage(0, compute::Access::Write);
    sweep_.dispatch(grid_.res);
    f.pressure.swap();
  }
}

SolveStats PressureJacobi::solve(FluidFields& f, const FluidParams& params) {
  SolveStats stats;
  if (params.pressure_tolerance <= 0.0f) {
    sweeps(f, params.pressure_iterations);
    stats.iterations = params.pressure_iterations;
    return stats;
  }
  if (!meter_) meter_ = std::make_unique<ResidualMeter>(grid_);
  stats.relative_residual = meter_->measure(f);
  stats.initial_relative_residual = stats.relative_residual;
  while (stats.relative_residual > params.pressure_tolerance && stats.iterations < params.pressure_iterations) {
    const int n = std::min(kCheckInterval, params.pressure_iterations - stats.iterations);
    sweeps(f, n);
    stats.iterations += n;
    stats.relative_residual = meter_->measure(f);
  }
  stats.converged = stats.relative_residual <= params.pressure_tolerance;
  return stats;
}

}  // namespace hf::fluid
