// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/pressure_multigrid.h"


#include <algorithm>
#include <cmath>
#include <utility>

#include "fluid/residual_meter.h"
#include "fluid/row_reduction.h"
#include "compute/workgroup.h"

namespace hf::fluid {
namespace {

// Result slots of the solver's reductions.
constexpr std::size_t kInitSlot = 0;  // (sum r, fluid cells, r.r, b.b) of the starting residual
constexpr std::size_t kSqSlot = 1;    // s.q
constexpr std::size_t kRzSlotA = 2;   // r.z, alternating with kRzSlotB (new and old)
constexpr std::size_t kRzSlotB = 3;
constexpr std::size_t kRrSlot = 4;    // (sum r, fluid cells, r.r) after an update
constexpr std::size_t kApSlot = 5;    // (b.r, Ap.Ap, b.Ap) of the warm start, for the predictor
constexpr std::size_t kSlots = 6;

}  // namespace

PressureMultigrid::PressureMultigrid(const Grid& grid)
    : grid_(grid),
      vcycle_(grid.res),
      r_(grid.res, compute::TexelFormat::R32F, "CG residual"),
      q_(grid.res, compute::TexelFormat::R32F, "CG A direction"),
      z_or_s_{compute::Texture3D(grid.res, compute::TexelFormat::R32F, "CG preconditioned residual or direction"),
              compute::Texture3D(grid.res, compute::TexelFormat::R32F, "CG preconditioned residual or direction")},
      init_("pcg_init.comp", rowGroupDefines()),
      apply_("pcg_apply.comp", rowGroupDefines()),
      dot_("pcg_dot.comp", rowGroupDefines()),
      update_("pcg_update.comp", rowGroupDefines()),
      direction_("pcg_direction.comp", compute::cellGroupDefines()),
      shift_("pressure_shift.comp", compute::cellGroupDefines()),
      predict_("pcg_predict.comp", rowGroupDefines()),
      reducer_(2 * rowCount(grid.res), kSlots),  // pcg_init writes two partials per row
      stale_(wholeGrid(grid.res)) {
  for (compute::ComputeProgram* p : {&init_, &apply_, &dot_, &update_, &direction_, &shift_, &predict_}) p->set("u_res", grid.res);
}

void PressureMultigrid::nextDirection(FluidFields& f, std::size_t rz_slot, std::size_t old_rz_slot, bool first) {
  vcycle_.apply(f.nbmask, f.face_open, r_, *z_);
  r_.bindImage(1, compute::Access::Read);
  z_->bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  reducer_.bindPartials(0);
  dot_.dispatch(rowInvocations(grid_.res));
  reducer_.reduce(rowCount(grid_.res), rz_slot);
  if (first) {
    std::swap(z_, s_);
    return;
  }
  s_->bindImage(0, compute::Access::ReadWrite);
  z_->bindImage(1, compute::Access::Read);
  f.nbmask.bindImage(2, compute::Access::Read);
  reducer_.bindResults(1);
  direction_.set("u_slot_new", static_cast<unsigned>(rz_slot));
  direction_.set("u_slot_old", static_cast<unsigned>(old_rz_slot));
  direction_.dispatch(grid_.res);
}

void PressureMultigrid::removeResidualMean(FluidFields& f, std::size_t slot) {
  r_.bindImage(0, compute::Access::ReadWrite);
  f.nbmask.bindImage(2, compute::Access::Read);
  reducer_.bindResults(1);
  shift_.set("u_slot", static_cast<unsigned>(slot));
  shift_.dispatch(grid_.res);
}

void PressureMultigrid::startResidual(FluidFields& f, bool predictor_sums, bool store) {
  f.pressure.cur().bindImage(1, compute::Access::Read);
  f.rhs.bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  f.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
  r_.bindImage(0, compute::Access::Write);
  reducer_.bindPartials(0);
  init_.set("u_predictor_sums", predictor_sums ? 1 : 0);
  init_.set("u_store_r", store ? 1 : 0);
  init_.dispatch(rowInvocations(grid_.res));
  reducer_.reduce(rowCount(grid_.res), kInitSlot);
  if (predictor_sums) reducer_.reduce(rowCount(grid_.res), kApSlot, rowCount(grid_.res));
}

SolveStats PressureMultigrid::solve(FluidFields& f, const FluidParams& params) {
  const std::size_t groups = rowCount(grid_.res);
  const float tolerance = params.pressure_tolerance;
  const bool closed = !params.open_top;
  // The obstacle's word (obstacleChanged) passed on to the textures, for what a device derives
  // from them (the CPU's regular rows).
  f.nbmask.changedOnlyIn(stale_.origin, stale_.extent);
  const CellBox faces = faceBox(stale_, grid_.res);
  f.face_open.changedOnlyIn(faces.origin, faces.extent);
  vcycle_.buildMasks(f.nbmask, f.face_open, stale_);
  stale_ = CellBox{};
  startResidual(f, true, true);
  predict(f, closed, tolerance > 0.0f);

  SolveStats stats;
  float bb = 0.0f;
  if (tolerance > 0.0f) {
    const glm::vec4 start = reducer_.readResults()[kInitSlot];
    bb = start.w;
    // What the solve starts from: the previous pressure scaled by the predictor's alpha (never
    // above 1 but for rounding: the min keeps the promise exact).
    stats.relative_residual = std::min(relativeResidual(start.z, bb), bb > 0.0f ? 1.0f : 0.0f);
    stats.initial_relative_residual = stats.relative_residual;
    if (stats.relative_residual <= tolerance) return stats;  // the warm start is good enough
  }

  std::size_t rz_new = kRzSlotA, rz_old = kRzSlotB;
  nextDirection(f, rz_new, rz_old, true);
  for (int k = 0; k < params.pressure_iterations; ++k) {
    // q = A s and s.q
    s_->bindImage(1, compute::Access::Read);
    f.nbmask.bindImage(3, compute::Access::Read);
    f.face_open.bindImage(kFaceOpenUnit, compute::Access::Read);
    q_.bindImage(0, compute::Access::Write);
    reducer_.bindPartials(0);
    apply_.dispatch(rowInvocations(grid_.res));
    reducer_.reduce(groups, kSqSlot);
    // p += alpha s, r -= alpha q, and r.r
    f.pressure.cur().bindImage(0, compute::Access::ReadWrite);
    r_.bindImage(1, compute::Access::ReadWrite);
    s_->bindImage(2, compute::Access::Read);
    q_.bindImage(3, compute::Access::Read);
    f.nbmask.bindImage(4, compute::Access::Read);
    reducer_.bindPartials(0);
    reducer_.bindResults(1);
    update_.set("u_slot_rz", static_cast<unsigned>(rz_new));
    update_.set("u_slot_sq", static_cast<unsigned>(kSqSlot));
    update_.dispatch(rowInvocations(grid_.res));
    reducer_.reduce(groups, kRrSlot);
    if (closed) removeResidualMean(f, kRrSlot);
    stats.iterations = k + 1;
    bool restart = false;
    if (tolerance > 0.0f) {
      stats.relative_residual = relativeResidual(reducer_.readResults()[kRrSlot].z, bb);
      if (stats.relative_residual <= tolerance) {
        // In float the updated residual drifts from the true one: confirm with rhs - A p (its
        // sums only), and if that is still too large go on from it (CG restarted from the true
        // residual, written then).
        startResidual(f, false, false);
        stats.relative_residual = relativeResidual(reducer_.readResults()[kInitSlot].z, bb);
        if (stats.relative_residual <= tolerance) break;
        startResidual(f, false, true);
        if (closed) removeResidualMean(f, kInitSlot);  // only r that goes on needs it
        restart = true;
      }
    }
    if (k + 1 == params.pressure_iterations) break;  // no direction needed after the last update
    std::swap(rz_new, rz_old);
    nextDirection(f, rz_new, rz_old, restart);
  }
  stats.converged = tolerance <= 0.0f || stats.relative_residual <= tolerance;
  return stats;
}

void PressureMultigrid::predict(FluidFields& f, bool remove_mean, bool sums) {
  f.pressure.cur().bindImage(0, compute::Access::ReadWrite);
  r_.bindImage(1, compute::Access::ReadWrite);
  f.rhs.bindImage(2, compute::Access::Read);
  f.nbmask.bindImage(3, compute::Access::Read);
  reducer_.bindPartials(0);
  reducer_.bindResults(1);
  predict_.set("u_slot_ap", static_cast<unsigned>(kApSlot));
  predict_.set("u_remove_mean", remove_mean ? 1 : 0);
  predict_.set("u_slot_mean", static_cast<unsigned>(kInitSlot));
  predict_.dispatch(rowInvocations(grid_.res));
  if (sums) reducer_.reduce(rowCount(grid_.res), kInitSlot);  // the new r's sums replace the warm start's
}

}  // namespace hf::fluid
