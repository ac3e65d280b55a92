// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/multigrid_vcycle.h"


#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>

#include "fluid/fluid_fields.h"
#include "compute/workgroup.h"

namespace hf::fluid {

namespace {
compute::Defines withProlong(compute::Defines d) {
  d.emplace_back("PROLONG", "1");
  return d;
}
}  // namespace

std::vector<glm::ivec3> MultigridVCycle::levelResolutions(const glm::ivec3& fine) {
  std::vector<glm::ivec3> out{fine};
  while (std::max(out.back().x, std::max(out.back().y, out.back().z)) > kCoarsestCells) {
    out.push_back((out.back() + 1) / 2);
  }
  return out;
}

MultigridVCycle::Coarse::Coarse(const glm::ivec3& r)
    : mask(r, compute::TexelFormat::R8UI, "multigrid mask"),
      faces(r + 1, compute::TexelFormat::RGBA32F, "multigrid face fractions"),
      x(r, compute::TexelFormat::R32F, "multigrid x"),
      b(r, compute::TexelFormat::R32F, "multigrid b") {}

MultigridVCycle::MultigridVCycle(const glm::ivec3& fine_res)
    : res_(levelResolutions(fine_res)),
      coarsen_("mg_coarsen_mask.comp", compute::cellGroupDefines()),
      coarsen_faces_("mg_coarsen_faces.comp", compute::cellGroupDefines()),
      residual_("mg_residual.comp", compute::cellGroupDefines()),
      restrict_("mg_restrict.comp", compute::cellGroupDefines()),
      prolong_("mg_prolong.comp", compute::cellGroupDefines()),
      coarsest_("mg_coarsest.comp", {{"COARSEST", std::to_string(kCoarsestCells)}}),
      smooth_prolong_("mg_smooth.comp", withProlong(compute::cellGroupDefines())),
      residual_restrict_("mg_residual_restrict.comp", compute::cellGroupDefines()) {
  coarse_.reserve(res_.size());
  for (std::size_t l = 1; l < res_.size(); ++l) coarse_.emplace_back(res_[l]);
  const int sweeps = 2 * smoothSweeps(fine_res);
  sweeps_.reserve(static_cast<std::size_t>(sweeps));
  for (int s = 0; s < sweeps; ++s) sweeps_.push_back(std::make_unique<compute::ComputeProgram>("mg_smooth.comp", compute::cellGroupDefines()));
}

int MultigridVCycle::smoothSweeps(const glm::ivec3& fine) {
  const long long cells = static_cast<long long>(fine.x) * fine.y * fine.z;
  return cells >= kLargeGridCells ? kSmoothSweepsLarge : kSmoothSweeps;
}

CellBox MultigridVCycle::coarseCells(const CellBox& fine, const glm::ivec3& coarse_res) {
  if (isEmpty(fine)) return fine;
  const glm::ivec3 first = glm::min(fine.origin / 2, coarse_res);
  const glm::ivec3 end = glm::min((fine.origin + fine.extent + 1) / 2, coarse_res);
  return {first, glm::max(end - first, glm::ivec3(0))};
}

void MultigridVCycle::coarsenMask(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask,
                                  const glm::ivec3& coarse_res, compute::Texture3D& coarse_mask, const CellBox& cells) {
  if (isEmpty(cells)) return;
  fine_mask.bindImage(1, compute::Access::Read);
  coarse_mask.bindImage(0, compute::Access::Write);
  coarsen_.set("u_res", coarse_res);
  coarsen_.set("u_fine_size", fine_res);
  coarsen_.set("u_origin", cells.origin);
  coarsen_.dispatch(cells.extent);
}

float MultigridVCycle::openTopWeight(int level) { return 1.0f / (0.5f + std::ldexp(0.5f, -level)); }

void MultigridVCycle::coarsenFaces(int coarse_level, const glm::ivec3& fine_res, const compute::Texture3D& fine_faces,
                                   const glm::ivec3& coarse_res, compute::Texture3D& coarse_faces, const CellBox& faces) {
  if (isEmpty(faces)) return;
  fine_faces.bindImage(1, compute::Access::Read);
  coarse_faces.bindImage(0, compute::Access::Write);
  coarsen_faces_.set("u_res", coarse_res);
  coarsen_faces_.set("u_fine_size", fine_res);
  coarsen_faces_.set("u_origin", faces.origin);
  coarsen_faces_.set("u_top_scale", openTopWeight(coarse_level) / openTopWeight(coarse_level - 1));
  coarsen_faces_.dispatch(faces.extent);
}

// A level's images as mg_smooth and mg_coarsest bind them: faces, x at 0 (`x_access`), b at 1,
// mask at 2.
void MultigridVCycle::bindSmoothInputs(const compute::Texture3D& mask, const compute::Texture3D& faces, compute::Texture3D& x,
                                       compute::Access x_access, const compute::Texture3D& b) {
  faces.bindImage(kFaceOpenUnit, compute::Access::Read);
  x.bindImage(0, x_access);
  b.bindImage(1, compute::Access::Read);
  mask.bindImage(2, compute::Access::Read);
}

// PROLONG's input: the next coarser level's x (mg_smooth.comp's u_coarse_x).
void MultigridVCycle::bindCoarseX(const compute::Texture3D& coarse_x) { coarse_x.bindImage(3, compute::Access::Read); }

// A program of mg_smooth.comp (plain or PROLONG) set for one red-black sweep of `colour` on a
// level of `res`; returns the sweep's invocations (one per cell of that colour).
glm::ivec3 MultigridVCycle::setSweep(compute::ComputeProgram& program, const glm::ivec3& res, int colour, bool zero_guess) {
  program.set("u_res", res);
  program.set("u_colour", colour);
  program.set("u_zero_guess", zero_guess ? 1 : 0);
  return glm::ivec3((res.x + 1) / 2, res.y, res.z);
}

// One red-black sweep of `colour` with mg_smooth.comp's program (plain or PROLONG): its images
// (bindSmoothInputs) and uniforms; PROLONG's coarse x is bound by the caller (bindCoarseX).
void MultigridVCycle::sweep(compute::ComputeProgram& program, const glm::ivec3& res, const compute::Texture3D& mask,
                            const compute::Texture3D& faces, compute::Texture3D& x, const compute::Texture3D& b, int colour,
                            bool zero_guess) {
  bindSmoothInputs(mask, faces, x, compute::Access::ReadWrite, b);
  program.dispatch(setSweep(program, res, colour, zero_guess));
}

// The residual's inputs, shared by mg_residual and mg_residual_restrict: faces, x at 1, b at 2,
// mask at 3 (the output at 0 is the caller's).
void MultigridVCycle::bindResidualInputs(const compute::Texture3D& mask, const compute::Texture3D& faces, const compute::Texture3D& x,
                                         const compute::Texture3D& b) {
  faces.bindImage(kFaceOpenUnit, compute::Access::Read);
  x.bindImage(1, compute::Access::Read);
  b.bindImage(2, compute::Access::Read);
  mask.bindImage(3, compute::Access::Read);
}

void MultigridVCycle::smooth(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
                             compute::Texture3D& x, const compute::Texture3D& b, int colour, bool zero_guess) {
  sweep(*sweeps_[0], res, mask, faces, x, b, colour, zero_guess);
}

void MultigridVCycle::residual(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
                               const compute::Texture3D& x, const compute::Texture3D& b, compute::Texture3D& out) {
  bindResidualInputs(mask, faces, x, b);
  out.bindImage(0, compute::Access::Write);
  residual_.set("u_res", res);
  residual_.dispatch(res);
}

void MultigridVCycle::restrictResidual(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask,
                                       const compute::Texture3D& fine_res_tex, const glm::ivec3& coarse_res,
                                       compute::Texture3D& coarse_b, float scale) {
  fine_res_tex.bindImage(1, compute::Access::Read);
  fine_mask.bindImage(2, compute::Access::Read);
  coarse_b.bindImage(0, compute::Access::Write);
  restrict_.set("u_res", coarse_res);
  restrict_.set("u_fine_size", fine_res);
  restrict_.set("u_scale", scale);
  restrict_.dispatch(coarse_res);
}

void MultigridVCycle::prolongAdd(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask, compute::Texture3D& fine_x,
                                 const compute::Texture3D& coarse_x) {
  fine_x.bindImage(0, compute::Access::ReadWrite);
  coarse_x.bindImage(1, compute::Access::Read);
  fine_mask.bindImage(2, compute::Access::Read);
  prolong_.set("u_res", fine_res);
  prolong_.dispatch(fine_res);
}

// The 2 smoothSweeps() sweeps on one side of a coarse correction, colours alternating from
// `colour`: `first`'s from its zero guess or not (PROLONG's coarse x bound by the caller,
// bindCoarseX), then sweeps_[1 ..]'s: the sweeps' result, which a device may compute in one pass
// (ComputeProgram::dispatchSeries; the CPU does, each sweep a plane behind the one before).
void MultigridVCycle::sweepSeries(compute::ComputeProgram& first, const glm::ivec3& res, const compute::Texture3D& mask,
                                  const compute::Texture3D& faces, compute::Texture3D& x, const compute::Texture3D& b,
                                  int colour, bool zero_guess) {
  bindSmoothInputs(mask, faces, x, compute::Access::ReadWrite, b);
  std::vector<std::pair<compute::ComputeProgram*, glm::ivec3>> series;
  series.emplace_back(&first, setSweep(first, res, colour, zero_guess));
  for (std::size_t s = 1; s < sweeps_.size(); ++s) {
    compute::ComputeProgram& sweep = *sweeps_[s];
    series.emplace_back(&sweep, setSweep(sweep, res, (colour + static_cast<int>(s)) % 2, false));
  }
  compute::ComputeProgram::dispatchSeries(series);
}

void MultigridVCycle::smoothProlonged(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
                                      compute::Texture3D& x, const compute::Texture3D& b, const compute::Texture3D& coarse_x,
                                      int colour) {
  bindCoarseX(coarse_x);
  sweep(smooth_prolong_, res, mask, faces, x, b, colour, false);
}

void MultigridVCycle::residualRestrict(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask,
                                       const compute::Texture3D& fine_faces, const compute::Texture3D& fine_x,
                                       const compute::Texture3D& fine_b, const glm::ivec3& coarse_res,
                                       compute::Texture3D& coarse_b, float scale) {
  bindResidualInputs(fine_mask, fine_faces, fine_x, fine_b);
  coarse_b.bindImage(0, compute::Access::Write);
  residual_restrict_.set("u_res", coarse_res);
  residual_restrict_.set("u_fine_size", fine_res);
  residual_restrict_.set("u_scale", scale);
  residual_restrict_.dispatch(coarse_res);
}

void MultigridVCycle::solveCoarsest(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
                                    compute::Texture3D& x, const compute::Texture3D& b) {
  bindSmoothInputs(mask, faces, x, compute::Access::Write, b);
  coarsest_.set("u_res", res);
  coarsest_.set("u_pairs", kCoarsestSweeps);
  coarsest_.dispatch(glm::ivec3(kCoarsestCells));
}

void MultigridVCycle::buildMasks(const compute::Texture3D& fine_mask, const compute::Texture3D& fine_faces,
                                 const CellBox& changed) {
  // A coarse cell reads its fine children's masks, a coarse face texel the fine face texels of
  // its children's faces on that side (faceBox of the children): coarseCells of the changed cells
  // and faceBox of those hold every cell and face texel that can change, on each level in turn.
  const compute::Texture3D* finer = &fine_mask;
  const compute::Texture3D* finer_faces = &fine_faces;
  CellBox cells = changed;
  for (std::size_t l = 1; l < res_.size() && !isEmpty(cells); ++l) {
    cells = coarseCells(cells, res_[l]);
    const CellBox faces = faceBox(cells, res_[l]);
    coarsenMask(res_[l - 1], *finer, res_[l], coarse_[l - 1].mask, cells);
    coarsenFaces(static_cast<int>(l), res_[l - 1], *finer_faces, res_[l], coarse_[l - 1].faces, faces);
    coarse_[l - 1].mask.changedOnlyIn(cells.origin, cells.extent);
    coarse_[l - 1].faces.changedOnlyIn(faces.origin, faces.extent);
    finer = &coarse_[l - 1].mask;
    finer_faces = &coarse_[l - 1].faces;
  }
}

void MultigridVCycle::apply(const compute::Texture3D& fine_mask, const compute::Texture3D& fine_faces, const compute::Texture3D& r,
                            compute::Texture3D& z) {
  // Level l's textures: level 0 is (fine_mask, fine_faces, z, r).
  struct View {
    const compute::Texture3D* mask;
    const compute::Texture3D* faces;
    compute::Texture3D* x;
    const compute::Texture3D* b;
  };
  std::vector<View> v;
  v.push_back({&fine_mask, &fine_faces, &z, &r});
  for (auto& c : coarse_) v.push_back({&c.mask, &c.faces, &c.x, &c.b});
  const int last = levels() - 1;
  auto level = [&](int l) { return res_[static_cast<std::size_t>(l)]; };

  for (int l = 0; l < last; ++l) {  // red, black, ... (smoothSweeps pairs)
    sweepSeries(*sweeps_[0], level(l), *v[l].mask, *v[l].faces, *v[l].x, *v[l].b, 0, true);
    residualRestrict(level(l), *v[l].mask, *v[l].faces, *v[l].x, *v[l].b, level(l + 1),
                     coarse_[static_cast<std::size_t>(l)].b, kCoarseScale);
  }
  solveCoarsest(level(last), *v[last].mask, *v[last].faces, *v[last].x, *v[last].b);
  for (int l = last - 1; l >= 0; --l) {
    // Black, red, ... (smoothSweeps pairs). The coarse correction is folded into the first sweep
    // (smoothProlonged's prolongAdd then smooth, in one pass).
    bindCoarseX(*v[l + 1].x);
    sweepSeries(smooth_prolong_, level(l), *v[l].mask, *v[l].faces, *v[l].x, *v[l].b, 1, false);
  }
}

}  // namespace hf::fluid
