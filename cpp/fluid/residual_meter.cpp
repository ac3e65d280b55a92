#include "fluid/residual_meter.h"

#include <GL/gl.h>

#include <cmath>

#include "gl/workgroup.h"

namespace hf::fluid {

ResidualMeter::ResidualMeter(const Grid& grid)
    : grid_(grid), residual_("residual.comp", gl::groupSumDefines()), reducer_(gl::groupCount(grid.res), 1) {
  residual_.set("u_res", grid.res);
}

float ResidualMeter::measure(FluidFields& f) {
  f.pressure.cur().bindImage(1, GL_READ_ONLY);
  f.rhs.bindImage(2, GL_READ_ONLY);
  f.nbmask.bindImage(3, GL_READ_ONLY);
  reducer_.bindPartials(0);
  residual_.dispatch(grid_.res);
  reducer_.reduce(gl::groupCount(grid_.res), 0);
  const glm::vec4 sums = reducer_.readResults()[0];
  if (sums.y > 0.0f) return std::sqrt(sums.x / sums.y);
  return sums.x == 0.0f ? 0.0f : INFINITY;
}

}  // namespace hf::fluid
