// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/fluid_solver.h"


#include <cmath>
#include <string>

#include "fluid/pressure_jacobi.h"
#include "fluid/pressure_multigrid.h"
#include "fluid/row_reduction.h"
#include "compute/workgroup.h"

namespace hf::fluid {
namespace {

constexpr int kScalarScratch = 3;

compute::Defines advectDefines(int field_at, bool pair) {
  compute::Defines d = compute::cellGroupDefines();
  d.emplace_back("FIELD_AT", std::to_string(field_at));
  if (pair) d.emplace_back("PAIR", "1");
  return d;
}

}  // namespace

FluidSolver::FluidSolver(const Grid& grid)
    : grid_(grid),
      fields_(grid),
      advect_{std::make_unique<compute::ComputeProgram>("advect.comp", advectDefines(0, false)),
              std::make_unique<compute::ComputeProgram>("advect.comp", advectDefines(1, false)),
              std::make_unique<compute::ComputeProgram>("advect.comp", advectDefines(2, false)),
              std::make_unique<compute::ComputeProgram>("advect.comp", advectDefines(kScalarScratch, false))},
      advect_pair_("advect.comp", advectDefines(kScalarScratch, true)),
      maccormack_("maccormack.comp", compute::cellGroupDefines()),
      sources_("sources.comp", compute::cellGroupDefines()),
      vorticity_("vorticity.comp", compute::cellGroupDefines()),
      cell_forces_("cell_forces.comp", compute::cellGroupDefines()),
      apply_forces_("apply_forces.comp", compute::cellGroupDefines()),
      boundaries_("enforce_boundaries.comp", compute::cellGroupDefines()),
      divergence_("divergence.comp", compute::cellGroupDefines()),
      residual_(grid),
      conservation_(grid),
      project_("project.comp", compute::cellGroupDefines()),
      pressure_sum_("pressure_sum.comp", rowGroupDefines()),
      pressure_shift_("pressure_shift.comp", compute::cellGroupDefines()),
      jacobi_(std::make_unique<PressureJacobi>(grid)) {
  for (auto& p : advect_) p->set("u_res", grid.res);
  for (compute::ComputeProgram* p : {&advect_pair_, &maccormack_, &sources_, &vorticity_, &cell_forces_, &apply_forces_,
                                &boundaries_, &divergence_, &project_, &pressure_sum_,
                                &pressure_shift_}) {
    p->set("u_res", grid.res);
  }
  vorticity_.set("u_cell_size", grid.cell_size_m);
  cell_forces_.set("u_cell_size", grid.cell_size_m);
}

void FluidSolver::reset() {
  for (auto& v : fields_.vel) for (auto& t : v.tex) t.clear();
  for (PingPong* f : {&fields_.density, &fields_.temperature, &fields_.pressure}) {
    for (auto& t : f->tex) t.clear();
  }
}

void FluidSolver::bindVelocityImages(unsigned first) {
  for (unsigned a = 0; a < 3; ++a) fields_.vel[a].cur().bindImage(first + a, compute::Access::Read);
}

void FluidSolver::advectField(compute::Texture3D& src, compute::Texture3D& dst, int scratch_kind, const glm::ivec3& size,
                              const glm::vec3& offset, float dt_s, float decay, bool zero_in_solid,
                              const FluidParams& p) {
  const float dt_over_h = dt_s / grid_.cell_size_m;
  compute::ComputeProgram& advect = *advect_[static_cast<std::size_t>(scratch_kind)];
  bindVelocityImages(2);  // advect.comp interpolates from images (units 2-4 velocity, 5 source)
  fields_.nbmask.bindImage(1, compute::Access::Read);
  advect.set("u_field_size", size);
  advect.set("u_field_offset", offset);
  if (p.advection == Advection::SemiLagrangian) {
    src.bindImage(5, compute::Access::Read);
    dst.bindImage(0, compute::Access::Write);
    advect.set("u_dt_over_h", dt_over_h);
    advect.set("u_decay", decay);
    advect.set("u_zero_in_solid", zero_in_solid ? 1 : 0);
    advect.dispatch(size);
    return;
  }
  PingPong& scratch = fields_.scratchFor(scratch_kind, size);
  compute::Texture3D& fwd = scratch.tex[0];
  compute::Texture3D& bwd = scratch.tex[1];
  advect.set("u_decay", 1.0f);
  advect.set("u_zero_in_solid", 0);
  src.bindImage(5, compute::Access::Read);
  fwd.bindImage(0, compute::Access::Write);
  advect.set("u_dt_over_h", dt_over_h);
  advect.dispatch(size);
  fwd.bindImage(5, compute::Access::Read);
  bwd.bindImage(0, compute::Access::Write);
  advect.set("u_dt_over_h", -dt_over_h);
  advect.dispatch(size);
  bindVelocityImages(5);  // maccormack.comp traces like advect.comp, from images (units 5-7)
  src.bindImage(4, compute::Access::Read);
  fwd.bindImage(2, compute::Access::Read);
  bwd.bindImage(3, compute::Access::Read);
  dst.bindImage(0, compute::Access::Write);
  maccormack_.set("u_field_size", size);
  maccormack_.set("u_field_offset", offset);
  maccormack_.set("u_dt_over_h", dt_over_h);
  maccormack_.set("u_decay", decay);
  maccormack_.set("u_zero_in_solid", zero_in_solid ? 1 : 0);
  maccormack_.dispatch(size);
}

void FluidSolver::advect(float dt_s, const FluidParams& p) {
  const float smoke_decay = std::exp(-p.density_dissipation_1_s * dt_s);
  const float heat_decay = std::exp(-p.temperature_dissipation_1_s * dt_s);
  // Before the velocity is advected: the outflow is carried by the velocity that moves the smoke.
  if (p.conserve_smoke) conservation_.measureBefore(fields_, dt_s, p.open_top);
  for (int a = 0; a < 3; ++a) {
    auto& v = fields_.vel[static_cast<std::size_t>(a)];
    advectField(v.cur(), v.next(), a, grid_.faceSize(a), Grid::faceOffset(a), dt_s, 1.0f, false, p);
  }
  if (p.advection == Advection::SemiLagrangian) {
    advectScalarPair(dt_s, smoke_decay, heat_decay);
  } else {
    advectField(fields_.density.cur(), fields_.density.next(), kScalarScratch, grid_.res, glm::vec3(0.5f), dt_s,
                smoke_decay, true, p);
    advectField(fields_.temperature.cur(), fields_.temperature.next(), kScalarScratch, grid_.res,
                glm::vec3(0.5f), dt_s, heat_decay, true, p);
  }
  for (auto& v : fields_.vel) v.swap();
  if (p.conserve_smoke) {
    conservation_.correct(fields_, smoke_decay, heat_decay);  // next() -> cur(): no swap
  } else {
    fields_.density.swap();
    fields_.temperature.swap();
  }
}

void FluidSolver::advectScalarPair(float dt_s, float smoke_decay, float heat_decay) {
  bindVelocityImages(2);
  fields_.nbmask.bindImage(1, compute::Access::Read);
  fields_.density.cur().bindImage(5, compute::Access::Read);
  fields_.density.next().bindImage(0, compute::Access::Write);
  fields_.temperature.cur().bindImage(6, compute::Access::Read);
  fields_.temperature.next().bindImage(7, compute::Access::Write);
  advect_pair_.set("u_field_size", grid_.res);
  advect_pair_.set("u_field_offset", glm::vec3(0.5f));
  advect_pair_.set("u_dt_over_h", dt_s / grid_.cell_size_m);
  advect_pair_.set("u_decay", smoke_decay);
  advect_pair_.set("u_decay2", heat_decay);
  advect_pair_.set("u_zero_in_solid", 1);
  advect_pair_.dispatch(grid_.res);
}

void FluidSolver::applySources(const SmokeSource& s, float dt_s) {
  if (!s.enabled) return;
  const glm::vec3 c = grid_.toGrid(s.centre_m);
  const float r = s.radius_m / grid_.cell_size_m;
  // Clamped as floats first: a huge radius must not overflow the integer conversion.
  const glm::vec3 res(grid_.res);
  const glm::ivec3 lo(glm::clamp(glm::floor(c - r), glm::vec3(0.0f), res - 1.0f));
  const glm::ivec3 hi(glm::clamp(glm::ceil(c + r), glm::vec3(0.0f), res));
  const glm::ivec3 extent = hi - lo;
  if (glm::any(glm::lessThanEqual(extent, glm::ivec3(0)))) return;
  fields_.density.cur().bindImage(0, compute::Access::ReadWrite);
  fields_.temperature.cur().bindImage(1, compute::Access::ReadWrite);
  fields_.nbmask.bindImage(2, compute::Access::Read);
  sources_.set("u_origin", lo);
  sources_.set("u_centre", c);
  sources_.set("u_radius", r);
  sources_.set("u_density_value", s.density);
  sources_.set("u_temperature_value", s.temperature_k);
  sources_.set("u_rate", s.emission == SourceEmission::Rate ? 1 : 0);
  sources_.set("u_dt", dt_s);
  sources_.dispatch(extent);
}

void FluidSolver::applyForces(float dt_s, const FluidParams& p) {
  const bool buoyant = p.smoke_weight_m_s2 != 0.0f || p.heat_buoyancy_m_s2_k != 0.0f;
  const bool confined = p.vorticity_confinement > 0.0f;
  if (!buoyant && !confined) return;
  if (confined) {
    bindVelocityImages(1);
    fields_.vorticity.bindImage(0, compute::Access::Write);
    vorticity_.dispatch(grid_.res);
  }
  const float g = glm::length(p.gravity_m_s2);
  const glm::vec3 up = g > 0.0f ? -p.gravity_m_s2 / g : glm::vec3(0.0f, 0.0f, 1.0f);
  fields_.density.cur().bindImage(1, compute::Access::Read);
  fields_.temperature.cur().bindImage(2, compute::Access::Read);
  fields_.vorticity.bindImage(3, compute::Access::Read);
  fields_.nbmask.bindImage(4, compute::Access::Read);
  fields_.cell_force.bindImage(0, compute::Access::Write);
  cell_forces_.set("u_up", up);
  cell_forces_.set("u_smoke_weight", p.smoke_weight_m_s2);
  cell_forces_.set("u_heat_buoyancy", p.heat_buoyancy_m_s2_k);
  cell_forces_.set("u_confinement", confined ? p.vorticity_confinement : 0.0f);
  cell_forces_.dispatch(grid_.res);
  fields_.cell_force.bindImage(1, compute::Access::Read);
  apply_forces_.set("u_dt", dt_s);
  for (int a = 0; a < 3; ++a) {
    fields_.vel[static_cast<std::size_t>(a)].cur().bindImage(0, compute::Access::ReadWrite);
    apply_forces_.set("u_axis", a);
    apply_forces_.dispatch(grid_.faceSize(a));
  }
}

void FluidSolver::enforceBoundaries(const FluidParams& p) {
  fields_.solid.bindImage(1, compute::Access::Read);
  fields_.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  fields_.solid_velocity.bindImage(2, compute::Access::Read);
  boundaries_.set("u_open_top", p.open_top ? 1 : 0);
  for (int a = 0; a < 3; ++a) {
    fields_.vel[static_cast<std::size_t>(a)].cur().bindImage(0, compute::Access::ReadWrite);
    boundaries_.set("u_axis", a);
    boundaries_.dispatch(grid_.faceSize(a));
  }
}

void FluidSolver::computeDivergence(float dt_s, const FluidParams& p) {
  bindVelocityImages(1);
  fields_.nbmask.bindImage(4, compute::Access::Read);
  fields_.solid_velocity.bindImage(5, compute::Access::Read);
  fields_.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  fields_.rhs.bindImage(0, compute::Access::Write);
  divergence_.set("u_scale", p.density_kg_m3 * grid_.cell_size_m / dt_s);
  divergence_.dispatch(grid_.res);
}

void FluidSolver::obstacleChanged(const CellBox& cells) {
  for (PressureSolver* s : {jacobi_.get(), multigrid_.get()}) {
    if (s) s->obstacleChanged(cells);
  }
}

SolveStats FluidSolver::solvePressure(const FluidParams& p) {
  if (p.pressure_solver == PressureSolverKind::Multigrid) {
    if (!multigrid_) multigrid_ = std::make_unique<PressureMultigrid>(grid_);
    return multigrid_->solve(fields_, p);
  }
  return jacobi_->solve(fields_, p);
}

void FluidSolver::removeRhsMean(compute::GroupReducer& reducer, std::size_t slot) { removeMean(fields_.rhs, reducer, slot); }

void FluidSolver::measureResidual(compute::GroupReducer& reducer, std::size_t slot) {
  residual_.accumulate(fields_, reducer, slot);
}

void FluidSolver::removePressureMean(compute::GroupReducer& reducer, std::size_t slot) {
  removeMean(fields_.pressure.cur(), reducer, slot);
}

// pressure_sum + reduce + pressure_shift work on any cell-centred scalar.
void FluidSolver::removeMean(compute::Texture3D& field, compute::GroupReducer& reducer, std::size_t slot) {
  field.bindImage(1, compute::Access::Read);
  fields_.nbmask.bindImage(2, compute::Access::Read);
  reducer.bindPartials(0);
  pressure_sum_.dispatch(rowInvocations(grid_.res));
  reducer.reduce(rowCount(grid_.res), slot);
  field.bindImage(0, compute::Access::ReadWrite);
  reducer.bindResults(1);
  pressure_shift_.set("u_slot", static_cast<unsigned>(slot));
  pressure_shift_.dispatch(grid_.res);
}

void FluidSolver::project(float dt_s, const FluidParams& p) {
  fields_.pressure.cur().bindImage(1, compute::Access::Read);
  fields_.nbmask.bindImage(2, compute::Access::Read);
  fields_.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  project_.set("u_open_top", p.open_top ? 1 : 0);
  project_.set("u_scale", dt_s / (p.density_kg_m3 * grid_.cell_size_m));
  for (int a = 0; a < 3; ++a) {
    fields_.vel[static_cast<std::size_t>(a)].cur().bindImage(0, compute::Access::ReadWrite);
    project_.set("u_axis", a);
    project_.dispatch(grid_.faceSize(a));
  }
}

}  // namespace hf::fluid
