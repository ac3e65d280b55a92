// SPDX-License-Identifier: GPL-3.0-or-later
#include "session/step_pipeline.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/finite.h"
#include "common/format.h"
#include "fluid/residual_meter.h"
#include "fluid/row_reduction.h"
#include "obstacle/obstacle.h"

namespace hf::session {
namespace {

constexpr std::size_t kForceSlot = 0;
constexpr std::size_t kResidualSlot = 1;
constexpr std::size_t kPressureMeanSlot = 2;
constexpr std::size_t kTorqueSlot = 3;
constexpr std::size_t kCentroidSlot = 4;
static_assert(kCentroidSlot < StepPipeline::kResultSlots);
constexpr force::ForceSlots kForceSlots{kForceSlot, kTorqueSlot, kCentroidSlot};

bool closedBox(const fluid::FluidParams& p) { return !p.open_top; }
bool residualAsked(const fluid::FluidParams& p) { return p.compute_residual; }

}  // namespace

struct StepPipeline::Pass {
  explicit Pass(const StepInputs& inputs) : in(inputs) {}
  const StepInputs& in;
  obstacle::Obstacle* body = nullptr;  // the probe voxelized this step, if any
  Footprint footprint;                 // what voxelize and classify compute this step
  obstacle::CellBox region;            // the cells they bring up to date
  fluid::SolveStats stats;             // of the pressure solve
  glm::vec3 p0_m{0.0f};                // the point the force stage summed torques about
  bool cut_cells = false;              // the body wrote geometric face fractions (else binary)
};

// The step, in order. A stage whose `runs` is false this step is skipped with its timer mark.
const StepPipeline::Stage StepPipeline::kStages[] = {
    {"voxelize", &StepPipeline::voxelize, nullptr},
    {"classify", &StepPipeline::classify, nullptr},
    {"advect", &StepPipeline::advect, nullptr},
    {"emit", &StepPipeline::emit, nullptr},
    {"forces", &StepPipeline::forces, nullptr},
    {"divergence", &StepPipeline::divergence, nullptr},
    {"pressure", &StepPipeline::pressure, nullptr},
    {"residual", &StepPipeline::residual, &residualAsked},
    {"project", &StepPipeline::project, nullptr},
    {"force", &StepPipeline::force, nullptr},
};

std::vector<const char*> StepPipeline::stageNames() {
  std::vector<const char*> names;
  for (const Stage& stage : kStages) names.push_back(stage.name);
  return names;
}

StepPipeline::StepPipeline(const fluid::Grid& g)
    : grid_(g), solver_(g), sphere_(g), classifier_(g), force_(g),
      reducer_(std::max(force::ForceReducer::partialsNeeded(g), fluid::rowCount(g.res)), kResultSlots) {}

StepPipeline::~StepPipeline() = default;

StepReport StepPipeline::step(const StepInputs& in) {
  Pass pass(in);
  timer_.begin();
  for (const Stage& stage : kStages) {
    if (stage.runs && !stage.runs(in.params)) continue;
    if (hook_.before) hook_.before(stage.name);
    (this->*stage.run)(pass);
    timer_.mark(stage.name);
    if (hook_.after) hook_.after(stage.name);
  }
  return report(pass, reducer_.readResults());  // the step's one read-back
}

void StepPipeline::voxelize(Pass& pass) {
  auto& f = solver_.fields();
  const std::optional<ProbeState>& probe = pass.in.probe;
  Footprint now;
  if (probe && probe->kind == ProbeState::Kind::Sphere) {
    sphere_.setPose(probe->sphere);
    sphere_.setCutCells(pass.in.params.cut_cells);
    pass.body = &sphere_;
    now.body = Footprint::Body::Sphere;
  } else if (probe) {
    if (!mesh_) mesh_ = std::make_unique<obstacle::MeshProbe>(grid_);
    mesh_->setMesh(probe->mesh);
    mesh_->setPose(probe->pose);
    mesh_->setCutCells(pass.in.params.cut_cells);
    pass.body = mesh_.get();
    now.body = Footprint::Body::Mesh;
  }
  now.cut_cells = pass.in.params.cut_cells;
  now.open_top = pass.in.params.open_top;
  if (pass.body) now.bounds = pass.body->bounds();
  pass.region = changedRegion(now);
  pass.footprint = now;
  footprint_.reset();  // until classify has brought every field up to date
  if (pass.body) {
    pass.body->voxelize(f.solid, f.solid_velocity, pass.region);
  } else if (!obstacle::isEmpty(pass.region)) {
    f.solid.clear();
    f.solid_velocity.clear();
  }
}

obstacle::CellBox StepPipeline::changedRegion(const Footprint& now) const {
  const obstacle::CellBox whole = obstacle::wholeGrid(grid_.res);
  if (!limit_to_probe_moves_ || !footprint_) return whole;
  const Footprint& last = *footprint_;
  // A change of body kind or of a setting can change any cell.
  if (now.body != last.body || now.cut_cells != last.cut_cells || now.open_top != last.open_top) {
    return whole;
  }
  // The cells whose solid flag, faces or neighbours' flags can change lie in the last and the new
  // bounds (each already a cell wider than the body and its cut faces' ramp); a cell beside them
  // sees a changed neighbour or face, hence one more cell.
  return obstacle::grownBox(obstacle::unionBox(last.bounds, now.bounds), 1, grid_.res);
}

void StepPipeline::classify(Pass& pass) {
  auto& f = solver_.fields();
  solver_.obstacleChanged(pass.region);  // before the writes: a stage that throws half-way is covered
  pass.cut_cells = pass.body && pass.body->writeFaceFractions(f.face_open, pass.region);
  if (!pass.cut_cells) classifier_.binaryFractions(f.solid, f.face_open, pass.region);
  classifier_.classify(f.solid, f.face_open, f.cell_class, f.nbmask, pass.in.params.open_top, pass.region);
  footprint_ = pass.footprint;
}

void StepPipeline::advect(Pass& pass) { solver_.advect(pass.in.dt_s, pass.in.params); }

void StepPipeline::emit(Pass& pass) {
  solver_.applySources(pass.in.source, pass.in.dt_s);
  if (!pass.in.mesh_source) return;
  if (!emitter_) emitter_ = std::make_unique<emitter::MeshEmitter>(grid_);
  auto& f = solver_.fields();
  emitter_->setSource(*pass.in.mesh_source);
  emitter_->voxelize();
  emitter_->emit(f.density.cur(), f.temperature.cur(), f.nbmask, pass.in.dt_s);
}

void StepPipeline::forces(Pass& pass) { solver_.applyForces(pass.in.dt_s, pass.in.params); }

void StepPipeline::divergence(Pass& pass) {
  solver_.enforceBoundaries(pass.in.params);
  solver_.computeDivergence(pass.in.dt_s, pass.in.params);
  if (closedBox(pass.in.params)) solver_.removeRhsMean(reducer_, kPressureMeanSlot);  // compatibility condition
}

void StepPipeline::pressure(Pass& pass) {
  pass.stats = solver_.solvePressure(pass.in.params);
  if (closedBox(pass.in.params)) solver_.removePressureMean(reducer_, kPressureMeanSlot);
}

void StepPipeline::residual(Pass&) { solver_.measureResidual(reducer_, kResidualSlot); }

void StepPipeline::project(Pass& pass) { solver_.project(pass.in.dt_s, pass.in.params); }

void StepPipeline::force(Pass& pass) {
  const obstacle::CellBox box = pass.body ? pass.body->bounds() : obstacle::CellBox{};
  pass.p0_m = pass.body ? pass.body->referencePointM() : glm::vec3(0.0f);
  auto& f = solver_.fields();
  // Only hydrostatic differences enter the force: pass.in.reference_m is not needed here.
  force_.reduce(f.pressure.cur(), f.cell_class, f.nbmask, f.face_open, box, pass.cut_cells, pass.in.rho_g,
                pass.p0_m, reducer_, kForceSlots);
}

StepReport StepPipeline::report(const Pass& pass, const std::vector<glm::vec4>& results) {
  const fluid::FluidParams& p = pass.in.params;
  StepReport r;
  const force::BodyForce bf = force::ForceReducer::decode(
      results, kForceSlots, pass.p0_m, pass.in.probe ? pass.in.probe->torque_centre_m : std::nullopt);
  r.force_n = bf.force_n;
  r.torque_n_m = bf.torque_n_m;
  r.torque_centre_m = bf.torque_centre_m;
  r.exposed_faces = bf.exposed_faces;
  r.solid_cells = bf.solid_cells;
  r.pressure_iterations = pass.stats.iterations;
  r.initial_relative_residual = pass.stats.initial_relative_residual;
  r.converged = pass.stats.converged;
  if (p.compute_residual) {
    const glm::vec4 res = results[kResidualSlot];
    r.relative_residual = fluid::relativeResidual(res.x, res.y);
  } else {
    r.relative_residual = pass.stats.relative_residual;  // the solver's own estimate in tolerance mode, else -1
  }
  r.gpu_ms = timer_.collect();
  const glm::vec4 mean = results[kPressureMeanSlot];
  if (!allFinite(r.force_n) || !allFinite(r.torque_n_m) ||
      (p.compute_residual && !std::isfinite(r.relative_residual)) || (closedBox(p) && !std::isfinite(mean.x))) {
    throw Error("the solver's state became non-finite (force " + vecText(r.force_n) +
                " N); call reset() and use a smaller time step or probe speed");
  }
  return r;
}

}  // namespace hf::session
