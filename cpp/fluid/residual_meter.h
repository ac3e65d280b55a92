#pragma once
// Measures the pressure equation's relative residual ||rhs - A p|| / ||rhs|| over the fluid
// cells now (residual.comp + a two-level reduction + a 16-byte read-back): the stopping test
// of the Jacobi solver's tolerance mode.
#include "fluid/fluid_fields.h"
#include "gl/compute_program.h"
#include "gl/group_reducer.h"

namespace hf::fluid {

class ResidualMeter {
 public:
  explicit ResidualMeter(const Grid& grid);
  // ||rhs - A p|| / ||rhs|| of fields.pressure.cur(); 0 when rhs and the residual are both 0.
  float measure(FluidFields& fields);

 private:
  Grid grid_;
  gl::ComputeProgram residual_;
  gl::GroupReducer reducer_;
};

}  // namespace hf::fluid
