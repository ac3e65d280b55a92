// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Jacobi iteration, ping-ponging the pressure textures: FluidParams::pressure_iterations sweeps,
// or with a pressure_tolerance, sweeps until the relative residual (measured every
// kCheckInterval sweeps) is at most the tolerance, at most pressure_iterations of them.
#include <memory>

#include "fluid/pressure_solver.h"
#include "fluid/residual_meter.h"
#include "compute/compute_program.h"

namespace hf::fluid {

class PressureJacobi : public PressureSolver {
 public:
  static constexpr int kCheckInterval = 16;  // sweeps between residual checks (tolerance mode)

  explicit PressureJacobi(const Grid& grid);
  const char* name() const override { return "jacobi"; }
  SolveStats solve(FluidFields& fields, const FluidParams& params) override;

 private:
  void sweeps(FluidFields& fields, int count);

  Grid grid_;
  compute::ComputeProgram sweep_;
  std::unique_ptr<ResidualMeter> meter_;  // made on the first solve with a tolerance
};

}  // namespace hf::fluid
