// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/scalar_conservation.h"


#include "fluid/row_reduction.h"
#include "compute/workgroup.h"

namespace hf::fluid {
namespace {
constexpr std::size_t kBeforeSlot = 0;
constexpr std::size_t kSmokeSlot = 1;
constexpr std::size_t kHeatSlot = 2;
constexpr std::size_t kSlots = 3;
}  // namespace

ScalarConservation::ScalarConservation(const Grid& grid)
    : grid_(grid),
      reducer_(2 * rowCount(grid.res), kSlots),
      total_("scalar_total.comp", rowGroupDefines()),
      headroom_("scalar_headroom.comp", rowGroupDefines()),
      correct_("scalar_correct.comp", compute::cellGroupDefines()) {
  for (compute::ComputeProgram* p : {&total_, &headroom_, &correct_}) p->set("u_res", grid.res);
}

void ScalarConservation::measureBefore(FluidFields& f, float dt_s, bool open_top) {
  f.density.cur().bindImage(1, compute::Access::Read);
  f.temperature.cur().bindImage(2, compute::Access::Read);
  f.vel[2].cur().bindImage(3, compute::Access::Read);
  reducer_.bindPartials(0);
  total_.set("u_open_top", open_top ? 1 : 0);
  total_.set("u_dt_over_h", dt_s / grid_.cell_size_m);
  total_.dispatch(rowInvocations(grid_.res));
  reducer_.reduce(rowCount(grid_.res), kBeforeSlot);
}

void ScalarConservation::correct(FluidFields& f, float smoke_decay, float heat_decay) {
  const std::size_t rows = rowCount(grid_.res);
  f.density.next().bindImage(1, compute::Access::Read);
  f.temperature.next().bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  reducer_.bindPartials(0);
  headroom_.dispatch(rowInvocations(grid_.res));
  reducer_.reduce(rows, kSmokeSlot, 0);
  reducer_.reduce(rows, kHeatSlot, rows);
  f.density.next().bindImage(1, compute::Access::Read);
  f.temperature.next().bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  f.density.cur().bindImage(4, compute::Access::Write);
  f.temperature.cur().bindImage(5, compute::Access::Write);
  reducer_.bindResults(1);
  correct_.set("u_decay", smoke_decay);
  correct_.set("u_decay2", heat_decay);
  correct_.dispatch(grid_.res);
}

}  // namespace hf::fluid
