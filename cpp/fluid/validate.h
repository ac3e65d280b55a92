#pragma once
// Checks of user-supplied settings; each throws hf::InvalidArgument saying what to change.
#include "fluid/fluid_params.h"
#include "fluid/grid.h"

namespace hf::fluid {

inline constexpr int kMaxPressureIterations = 100000;

void validate(const FluidParams& params);
void validate(const SmokeSource& source, const Grid& grid);

}  // namespace hf::fluid
