// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The interface every pressure solver shares (PressureJacobi, PressureMultigrid): solve
// sum_nb (p_nb - p) = rhs over the fluid cells into fields.pressure.cur(), warm-started from
// the previous step's pressure.
#include "fluid/cell_box.h"
#include "fluid/fluid_fields.h"
#include "fluid/fluid_params.h"

namespace hf::fluid {

struct SolveStats {
  int iterations = 0;
  float relative_residual = -1.0f;  // ||r|| / ||rhs||, filled in after the step's read-back; -1 = not measured
  // Tolerance mode: ||r|| / ||rhs|| of the warm start, before the first iteration; -1 = not measured.
  float initial_relative_residual = -1.0f;
  // Tolerance mode: false when the solve stopped at the iteration cap above the tolerance.
  // Always true in fixed-count mode (it promises no residual).
  bool converged = true;
};

class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  virtual const char* name() const = 0;
  virtual SolveStats solve(FluidFields& fields, const FluidParams& params) = 0;
  // Whoever writes the fields' nbmask or face_open says which cells it may have changed (their
  // faces: faceBox) before the next solve: a solver may keep what it derives from them
  // (PressureMultigrid's coarse levels). A new solver derives everything on its first solve.
  virtual void obstacleChanged(const CellBox& cells) { (void)cells; }
};

}  // namespace hf::fluid
