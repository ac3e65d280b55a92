#pragma once
// Jacobi iteration, a fixed number of sweeps (FluidParams::pressure_iterations), ping-ponging
// the pressure textures.
#include "fluid/pressure_solver.h"
#include "gl/compute_program.h"

namespace hf::fluid {

class PressureJacobi : public PressureSolver {
 public:
  explicit PressureJacobi(const Grid& grid);
  const char* name() const override { return "jacobi"; }
  SolveStats solve(FluidFields& fields, const FluidParams& params) override;

 private:
  Grid grid_;
  gl::ComputeProgram sweep_;
};

}  // namespace hf::fluid
