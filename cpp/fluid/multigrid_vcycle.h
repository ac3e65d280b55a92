// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A geometric multigrid V-cycle for A x = b, A x = n x - sum of the linked neighbours' x (the
// pressure operator with the sign that makes it positive semidefinite; n counts the linked
// neighbours and the open-top ghost, as in shaders/common.glsl's neighbour mask). Used as the
// preconditioner of PressureMultigrid's conjugate gradient: apply() gives z = M r from z = 0.
//
// Levels: level 0 is the simulation grid; each coarser level has ceil(n / 2) cells per axis
// (any resolution, not only powers of two) down to at most kCoarsestCells per axis. Coarse
// masks come from the fine one (mg_coarsen_mask.comp): a coarse cell is fluid if any child is,
// linked across a side if a fluid child is, and sees the open top if a fluid child does; coarse
// face fractions (cut cells) are the mean of the fine faces they are made of (mg_coarsen_faces.comp),
// and every level's operator weights each link by its face's open fraction; the open top's
// fraction is also weighted by openTopWeight, which puts its zero where the fine grid's is.
// Transfer is piecewise constant (prolongation P) and its transpose (restriction P^T, times
// kCoarseScale); smoothing is red-black Gauss-Seidel, red then black before the coarse
// correction and black then red after it, and the coarsest level is solved by symmetric
// red-black sweeps (one dispatch, mg_coarsest.comp), so M is symmetric positive definite as CG
// needs.
#include <memory>
#include <vector>

#include "compute/compute_program.h"
#include "compute/texture3d.h"
#include "fluid/cell_box.h"

namespace hf::fluid {

class MultigridVCycle {
 public:
  static constexpr int kCoarsestCells = 4;   // stop coarsening once no axis has more cells
  // mg_coarsest solves the coarsest level in one workgroup of kCoarsestCells^3 invocations: GL
  // guarantees 1024 invocations per workgroup and 64 along z.
  static_assert(kCoarsestCells * kCoarsestCells * kCoarsestCells <= 1024 && kCoarsestCells <= 64);
  // Red-black sweeps before and after the correction, on every level (smoothSweeps): two, or
  // three where the fine grid has at least kLargeGridCells cells. Three cost 1.5 times the
  // smoothing and save CG iterations (to 1e-3: the seed grid 2.0 instead of 3, 48^3 with an open
  // top 2.8 instead of 3.8, 32^3 2.8 instead of 3.4), each of which also costs about eight passes
  // over the fine grid: on a grid that leaves the caches those passes go to memory and three
  // sweeps win (the seed grid's pressure on one thread 33.9 -> 28.7 ms, llvmpipe's 246 -> 199),
  // on a small one they do not (32^3 2.8 -> 3.2 ms). Three on one kind of level only, fine or
  // coarse, kept 3 iterations on the seed grid. docs/BENCHMARKS.md, 2026-12-07. (Those open-top
  // figures are from before openTopWeight: with it 48^3 takes 2.0, and 32^3 2.9 with two sweeps,
  // 2.3 with three, at the same cost: 2.02-2.18 against 2.07-2.26 ms on one thread.)
  static constexpr int kSmoothSweeps = 2;
  static constexpr int kSmoothSweepsLarge = 3;
  static constexpr long long kLargeGridCells = 65536;
  static int smoothSweeps(const glm::ivec3& fine_res);
  // The open top's weight on `level`, relative to a link's: the fine grid's open top is a ghost
  // cell at p = 0 above the top face, so its zero lies half a fine cell h above the face; a cell of
  // level l (size 2^l h) has its centre 2^(l-1) h below the face, so its ghost term is
  // 2^l h / (2^(l-1) h + h / 2) = 1 / (1/2 + 2^-(l+1)) times a link's (1 on the fine grid, 4/3, 1.6,
  // 1.78, ... below). With the fine grid's weight of 1 on every level (the piecewise-constant
  // Galerkin operator's) the coarse levels put the zero too close, and an open box converged
  // slowly: CG iterations to 1e-3 at 48^3 3.0 -> 2.0, 32^3 3.3 -> 3.0, 64^3 3.2 -> 2.5 (a closed
  // box has no open top). mg_coarsen_faces applies the ratio of a level's weight to the finer
  // one's to the top faces it coarsens. docs/BENCHMARKS.md, 2026-12-07 (night).
  static float openTopWeight(int level);
  static constexpr int kCoarsestSweeps = 12; // symmetric pairs of sweeps on the coarsest level
  // The coarse right-hand side is kCoarseScale * P^T r. The Galerkin operator P^T A P of
  // piecewise-constant P is 4 times the coarse 7-point stencil (four fine faces per coarse
  // face), which gives 1/4; the classic over-correction of piecewise-constant transfer for the
  // Poisson equation (it underestimates smooth errors by about 2) gives 1/2, which measured
  // fewer CG iterations here.
  static constexpr float kCoarseScale = 0.5f;

  // Resolutions of every level, finest first.
  static std::vector<glm::ivec3> levelResolutions(const glm::ivec3& fine);

  explicit MultigridVCycle(const glm::ivec3& fine_res);

  int levels() const { return static_cast<int>(res_.size()); }
  const glm::ivec3& resolution(int level) const { return res_[static_cast<std::size_t>(level)]; }

  // Brings every coarse mask and face-fraction image up to date with the fine ones (once per
  // step: the solid moves), rebuilding on each level only the cells and faces made of the fine
  // level's `changed` cells and their faces (the coarse levels keep the rest from the last call):
  // wholeGrid(resolution(0)) on the first call and whenever what changed is not known.
  // `fine_faces`: the fine level's face fractions (shaders/common.glsl).
  void buildMasks(const compute::Texture3D& fine_mask, const compute::Texture3D& fine_faces, const CellBox& changed);
  // z = M r from z = 0. Call buildMasks first.
  void apply(const compute::Texture3D& fine_mask, const compute::Texture3D& fine_faces, const compute::Texture3D& r,
             compute::Texture3D& z);

  // The coarse cells made of a box of fine cells (children 2c and 2c + 1 of coarse cell c), on a
  // coarse level of `coarse_res` cells.
  static CellBox coarseCells(const CellBox& fine, const glm::ivec3& coarse_res);

  // The stages, public for tests. `res` is the resolution of the level the textures have.
  // coarsenMask rebuilds the coarse cells of `cells`, coarsenFaces the coarse face texels of
  // `faces` (of coarse_res + 1 per axis) of level `coarse_level` (>= 1: its open top's weight).
  void coarsenMask(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask, const glm::ivec3& coarse_res,
                   compute::Texture3D& coarse_mask, const CellBox& cells);
  void coarsenFaces(int coarse_level, const glm::ivec3& fine_res, const compute::Texture3D& fine_faces,
                    const glm::ivec3& coarse_res, compute::Texture3D& coarse_faces, const CellBox& faces);
  void smooth(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces, compute::Texture3D& x,
              const compute::Texture3D& b, int colour, bool zero_guess);
  void residual(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces, const compute::Texture3D& x,
                const compute::Texture3D& b, compute::Texture3D& out);
  void restrictResidual(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask, const compute::Texture3D& fine_res_tex,
                        const glm::ivec3& coarse_res, compute::Texture3D& coarse_b, float scale);
  void prolongAdd(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask, compute::Texture3D& fine_x,
                  const compute::Texture3D& coarse_x);
  // The fused stages. smoothProlonged: prolongAdd(coarse_x) then a sweep of `colour`, in one pass
  // (mg_smooth.comp with PROLONG; valid as the first sweep after the correction, whose next sweep
  // rewrites the other colour; apply() runs it as the first of a sweep series). residualRestrict:
  // residual() then restrictResidual() without storing the fine residual (mg_residual_restrict.comp).
  void smoothProlonged(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
                       compute::Texture3D& x, const compute::Texture3D& b, const compute::Texture3D& coarse_x, int colour);
  void residualRestrict(const glm::ivec3& fine_res, const compute::Texture3D& fine_mask, const compute::Texture3D& fine_faces,
                        const compute::Texture3D& fine_x, const compute::Texture3D& fine_b, const glm::ivec3& coarse_res,
                        compute::Texture3D& coarse_b, float scale);
  // The coarsest level's kCoarsestSweeps symmetric pairs of red-black sweeps from x = 0, in one
  // dispatch (mg_coarsest.comp: the same arithmetic as the smooth() calls). Every axis of `res`
  // must be at most kCoarsestCells.
  void solveCoarsest(const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces, compute::Texture3D& x,
                     const compute::Texture3D& b);

  // Texture of a coarse level (level >= 1), for tests.
  compute::Texture3D& mask(int level) { return coarse_[static_cast<std::size_t>(level - 1)].mask; }
  compute::Texture3D& faces(int level) { return coarse_[static_cast<std::size_t>(level - 1)].faces; }

 private:
  static void bindCoarseX(const compute::Texture3D& coarse_x);
  static glm::ivec3 setSweep(compute::ComputeProgram& program, const glm::ivec3& res, int colour, bool zero_guess);
  void sweepSeries(compute::ComputeProgram& first, const glm::ivec3& res, const compute::Texture3D& mask,
                   const compute::Texture3D& faces, compute::Texture3D& x, const compute::Texture3D& b, int colour,
                   bool zero_guess);
  void sweep(compute::ComputeProgram& program, const glm::ivec3& res, const compute::Texture3D& mask, const compute::Texture3D& faces,
             compute::Texture3D& x, const compute::Texture3D& b, int colour, bool zero_guess);
  static void bindSmoothInputs(const compute::Texture3D& mask, const compute::Texture3D& faces, compute::Texture3D& x,
                               compute::Access x_access, const compute::Texture3D& b);
  static void bindResidualInputs(const compute::Texture3D& mask, const compute::Texture3D& faces, const compute::Texture3D& x,
                                 const compute::Texture3D& b);

  struct Coarse {
    explicit Coarse(const glm::ivec3& res);
    compute::Texture3D mask, faces, x, b;
  };

  std::vector<glm::ivec3> res_;
  std::vector<Coarse> coarse_;  // levels 1 .. levels()-1
  compute::ComputeProgram coarsen_;
  compute::ComputeProgram coarsen_faces_;
  compute::ComputeProgram residual_;
  compute::ComputeProgram restrict_;
  compute::ComputeProgram prolong_;
  compute::ComputeProgram coarsest_;
  compute::ComputeProgram smooth_prolong_;
  compute::ComputeProgram residual_restrict_;
  // mg_smooth for each sweep of a sweepSeries (each keeps its own uniforms; the first of the
  // smoothing after a correction is smooth_prolong_ instead); smooth() uses the first.
  std::vector<std::unique_ptr<compute::ComputeProgram>> sweeps_;
};

}  // namespace hf::fluid
