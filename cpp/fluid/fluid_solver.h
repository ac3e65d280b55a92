// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The smoke solver on the GPU, one method per stage (GPU Gems 3 ch. 30 order):
//   advect(); applySources(); applyForces(); enforceBoundaries(); computeDivergence();
//   solvePressure(); project();
// It reads the solid mask and solid velocity that an obstacle wrote into fields(), without
// knowing the obstacle's shape.
#include <array>
#include <memory>

#include "fluid/fluid_fields.h"
#include "fluid/fluid_params.h"
#include "fluid/grid.h"
#include "fluid/pressure_solver.h"
#include "fluid/residual_meter.h"
#include "fluid/scalar_conservation.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"

namespace hf::fluid {

class FluidSolver {
 public:
  explicit FluidSolver(const Grid& grid);

  const Grid& grid() const { return grid_; }
  FluidFields& fields() { return fields_; }

  void advect(float dt_s, const FluidParams& p);
  void applySources(const SmokeSource& source, float dt_s);  // the sphere source (dt for Rate)
  void applyForces(float dt_s, const FluidParams& p);  // buoyancy + vorticity confinement
  void enforceBoundaries(const FluidParams& p);        // walls and solid faces
  void computeDivergence(float dt_s, const FluidParams& p);
  // Closed box only: shifts the rhs so its mean over fluid cells is 0, the compatibility
  // condition of the pure-Neumann problem (sum in `slot`). Call after computeDivergence().
  void removeRhsMean(compute::GroupReducer& reducer, std::size_t slot);
  // The obstacle stages (StepPipeline) changed the nbmask and face_open of at most these cells
  // (and their faces): every pressure solver hears it before its next solve.
  void obstacleChanged(const CellBox& cells);
  // Runs the solver p.pressure_solver names (made on first use).
  SolveStats solvePressure(const FluidParams& p);
  // First level of ||r||^2, ||rhs||^2 into the reducer's partials, summed into `slot`. This
  // and the mean removals write rowCount(res) partials (fluid/row_reduction.h).
  void measureResidual(compute::GroupReducer& reducer, std::size_t slot);
  // Closed box only: shifts the pressure so its mean over fluid cells is 0 (sum into `slot`).
  void removePressureMean(compute::GroupReducer& reducer, std::size_t slot);
  void project(float dt_s, const FluidParams& p);

  // Zeroes velocity, smoke, heat and pressure.
  void reset();

 private:
  void advectField(compute::Texture3D& src, compute::Texture3D& dst, int scratch_kind, const glm::ivec3& size,
                   const glm::vec3& offset, float dt_s, float decay, bool zero_in_solid,
                   const FluidParams& p);
  // Smoke and heat in one semi-Lagrangian pass (advect_pair_).
  void advectScalarPair(float dt_s, float smoke_decay, float heat_decay);
  void bindVelocityImages(unsigned first);  // read-only image units first..first+2
  void removeMean(compute::Texture3D& field, compute::GroupReducer& reducer, std::size_t slot);

  Grid grid_;
  FluidFields fields_;
  // advect.comp per field kind (0-2: velocity on that axis's faces, 3: a scalar), and the
  // variant that carries smoke and heat through one back-trace.
  std::array<std::unique_ptr<compute::ComputeProgram>, 4> advect_;
  compute::ComputeProgram advect_pair_;
  compute::ComputeProgram maccormack_;
  compute::ComputeProgram sources_;
  compute::ComputeProgram vorticity_;
  compute::ComputeProgram cell_forces_;
  compute::ComputeProgram apply_forces_;
  compute::ComputeProgram boundaries_;
  compute::ComputeProgram divergence_;
  ResidualMeter residual_;
  ScalarConservation conservation_;
  compute::ComputeProgram project_;
  compute::ComputeProgram pressure_sum_;
  compute::ComputeProgram pressure_shift_;
  std::unique_ptr<PressureSolver> jacobi_;
  std::unique_ptr<PressureSolver> multigrid_;
};

}  // namespace hf::fluid
