// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Keeps advection from creating or destroying smoke and heat. Semi-Lagrangian and MacCormack
// transport are not conservative (a hot puff in a closed box lost 9% in 0.9 s); this measures
// each field's total before advection (and, with an open top, what the velocity carries out
// through the top faces, a real outflow), and after it gives the difference back to the fluid
// cells in proportion to their room to rise or fall within their neighbours' range, so no new
// extremum appears (shaders scalar_total, scalar_headroom, scalar_correct; docs/ARCHITECTURE.md).
// Dissipation is applied by advection and kept: the target is decay * (before - outflow).
// Cost: three passes over the grid and three small reductions, no read-back.
#include <glm/glm.hpp>

#include "fluid/fluid_fields.h"
#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"

namespace hf::fluid {

class ScalarConservation {
 public:
  explicit ScalarConservation(const Grid& grid);

  // Totals of fields.density.cur() and fields.temperature.cur() and the top outflow that the
  // velocity fields.vel[2].cur() carries in dt_s (open_top only). Call before advection.
  void measureBefore(FluidFields& fields, float dt_s, bool open_top);
  // Reads the advected fields in density.next() / temperature.next() and writes the corrected
  // ones into density.cur() / temperature.cur() (the caller then does not swap them).
  // smoke_decay and heat_decay: the dissipation multipliers advection applied.
  void correct(FluidFields& fields, float smoke_decay, float heat_decay);

 private:
  Grid grid_;
  compute::GroupReducer reducer_;  // slot 0: before (smoke, heat, outflows); 1, 2: after (smoke, heat)
  compute::ComputeProgram total_;
  compute::ComputeProgram headroom_;
  compute::ComputeProgram correct_;
};

}  // namespace hf::fluid
