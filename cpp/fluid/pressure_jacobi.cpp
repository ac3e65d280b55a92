#include "fluid/pressure_jacobi.h"

#include <GL/gl.h>

#include "gl/workgroup.h"

namespace hf::fluid {

PressureJacobi::PressureJacobi(const Grid& grid) : grid_(grid), sweep_("jacobi.comp", gl::cellGroupDefines()) {
  sweep_.set("u_res", grid.res);
}

SolveStats PressureJacobi::solve(FluidFields& f, const FluidParams& params) {
  f.rhs.bindImage(2, GL_READ_ONLY);
  f.nbmask.bindImage(3, GL_READ_ONLY);
  for (int i = 0; i < params.pressure_iterations; ++i) {
    f.pressure.cur().bindImage(1, GL_READ_ONLY);
    f.pressure.next().bindImage(0, GL_WRITE_ONLY);
    sweep_.dispatch(grid_.res);
    f.pressure.swap();
  }
  SolveStats stats;
  stats.iterations = params.pressure_iterations;
  return stats;
}

}  // namespace hf::fluid
