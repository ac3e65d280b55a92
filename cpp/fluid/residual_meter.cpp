#include "fluid/residual_meter.h"

#include <GL/gl.h>

#include <cmath>

#include "fluid/row_reduction.h"

namespace hf::fluid {

ResidualMeter::ResidualMeter(const Grid& grid)
    : grid_(grid), residual_("residual.comp", rowGroupDefines()), reducer_(rowCount(grid.res), 1) {
  residual_.set("u_res", grid.res);
}

float ResidualMeter::measure(FluidFields& f) {
  f.pressure.cur().bindImage(1, GL_READ_ONLY);
  f.rhs.bindImage(2, GL_READ_ONLY);
  f.nbmask.bindImage(3, GL_READ_ONLY);
  reducer_.bindPartials(0);
  residual_.dispatch(rowInvocations(grid_.res));
  reducer_.reduce(rowCount(grid_.res), 0);
  const glm::vec4 sums = reducer_.readResults()[0];
  if (sums.y > 0.0f) return std::sqrt(sums.x / sums.y);
  return sums.x == 0.0f ? 0.0f : INFINITY;
}

}  // namespace hf::fluid
