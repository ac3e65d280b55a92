// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The pressure equation's relative residual ||rhs - A p|| / ||rhs|| over the fluid cells
// (residual.comp + a two-level reduction). accumulate() adds its sums to a caller's reducer (the
// step's one read-back); measure() reads them back now (16 bytes): the stopping test of the
// Jacobi solver's tolerance mode.
#include <cmath>
#include <memory>

#include "fluid/fluid_fields.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"

namespace hf::fluid {

// sqrt(rr / bb) from the sums of r.r and rhs.rhs; 0 when both are 0, infinite when only the
// rhs is 0.
inline float relativeResidual(float rr, float bb) {
  if (bb > 0.0f) return std::sqrt(rr / bb);
  return rr == 0.0f ? 0.0f : INFINITY;
}

class ResidualMeter {
 public:
  explicit ResidualMeter(const Grid& grid);
  // First level of ||r||^2, ||rhs||^2 of fields.pressure.cur() into `reducer`'s partials,
  // summed into `slot` (x: r.r, y: rhs.rhs).
  void accumulate(FluidFields& fields, compute::GroupReducer& reducer, std::size_t slot);
  // ||rhs - A p|| / ||rhs|| of fields.pressure.cur() (relativeResidual), read back now.
  float measure(FluidFields& fields);

 private:
  Grid grid_;
  compute::ComputeProgram residual_;
  std::unique_ptr<compute::GroupReducer> reducer_;  // measure()'s own, made on first use
};

}  // namespace hf::fluid
