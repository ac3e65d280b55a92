// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/residual_meter.h"


#include "fluid/row_reduction.h"

namespace hf::fluid {

ResidualMeter::ResidualMeter(const Grid& grid) : grid_(grid), residual_("residual.comp", rowGroupDefines()) {
  residual_.set("u_res", grid.res);
}

void ResidualMeter::accumulate(FluidFields& f, compute::GroupReducer& reducer, std::size_t slot) {
  f.pressure.cur().bindImage(1, compute::Access::Read);
  f.rhs.bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  f.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  reducer.bindPartials(0);
  residual_.dispatch(rowInvocations(grid_.res));
  reducer.reduce(rowCount(grid_.res), slot);
}

float ResidualMeter::measure(FluidFields& f) {
  if (!reducer_) reducer_ = std::make_unique<compute::GroupReducer>(rowCount(grid_.res), 1);
  accumulate(f, *reducer_, 0);
  const glm::vec4 sums = reducer_->readResults()[0];
  return relativeResidual(sums.x, sums.y);
}

}  // namespace hf::fluid
