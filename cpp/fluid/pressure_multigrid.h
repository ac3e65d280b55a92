// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Conjugate gradient preconditioned by a multigrid V-cycle (MGPCG, as in McAdams, Sifakis and
// Teran, "A parallel multigrid Poisson solver for fluids simulation on large grids", SCA 2010),
// started from the previous step's pressure scaled to the least starting residual (predict()).
// Every vector operation and both dot
// products of an iteration run on the GPU; alpha and beta are read by the shaders from the
// reduction results, so the fixed-count mode never waits for a read-back.
//
// Modes (FluidParams): pressure_tolerance == 0 runs pressure_iterations CG iterations (one
// V-cycle each); pressure_tolerance > 0 stops as soon as the CG residual ||r|| / ||rhs|| is at
// most the tolerance (read back after every iteration; confirmed against the true residual
// rhs - A p, since in float the updated one drifts), after at most pressure_iterations.
// In a closed box the rhs must have zero mean over the fluid cells (FluidSolver::removeRhsMean
// does that before the solve), the CG residual's mean is removed every iteration, and the
// pressure's free constant is removed after the solve.
#include "fluid/multigrid_vcycle.h"
#include "fluid/pressure_solver.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"

namespace hf::fluid {

class PressureMultigrid : public PressureSolver {
 public:
  explicit PressureMultigrid(const Grid& grid);
  const char* name() const override { return "multigrid"; }
  SolveStats solve(FluidFields& fields, const FluidParams& params) override;
  void obstacleChanged(const CellBox& cells) override { stale_ = unionBox(stale_, cells); }

 private:
  // r = -rhs - A p, its sums into the init slot (and with `predictor_sums` b.r, Ap.Ap, b.Ap into
  // the predictor's); r itself is written only with `store` (not when only its norm confirms the
  // end of the solve). In a closed box the caller removes r's mean where r is used further.
  void startResidual(FluidFields& f, bool predictor_sums, bool store);
  // After startResidual(..., true): p = alpha p and r = b - alpha A p with the alpha that
  // minimises ||r|| (pcg_predict.comp, decided on the GPU): never worse than p = 0 or than p.
  // With `remove_mean` (a closed box) r's mean is removed first (removeResidualMean's, in the same
  // pass). With `sums` the new r's (sum r, fluid cells, r.r, b.b) replace the init slot's.
  void predict(FluidFields& f, bool remove_mean, bool sums);
  // r -= its mean over fluid cells (sum and count in results[slot].xy). In a closed box A is
  // singular (constants); a residual with a constant part, which float rounding leaves, would
  // make the V-cycle return a huge constant and CG's step sizes meaningless.
  void removeResidualMean(FluidFields& f, std::size_t slot);
  // z = M r, r.z into results[rz_slot], then s = z + beta s, or when `first` s = z: z's texture
  // becomes s's and s's the next z's (the V-cycle writes every cell of z before it reads one, and
  // z is 0 in solid cells as s is), so the first direction costs no pass.
  void nextDirection(FluidFields& f, std::size_t rz_slot, std::size_t old_rz_slot, bool first);

  Grid grid_;
  MultigridVCycle vcycle_;
  compute::Texture3D r_, q_;  // CG residual, A s
  compute::Texture3D z_or_s_[2];  // the preconditioned residual and the direction, in turn
  compute::Texture3D* z_ = &z_or_s_[0];
  compute::Texture3D* s_ = &z_or_s_[1];
  compute::ComputeProgram init_, apply_, dot_, update_, direction_, shift_, predict_;
  compute::GroupReducer reducer_;
  CellBox stale_;  // the fine cells changed since the coarse levels were last built (all at first)
};

}  // namespace hf::fluid
