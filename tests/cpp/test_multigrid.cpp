// SPDX-License-Identifier: GPL-3.0-or-later
// The multigrid pressure solver: its transfer stages against CPU references on tiny grids of
// odd sizes, the level sizes of resolutions that are not powers of two, and the whole solve
// (conjugate gradient preconditioned by the V-cycle) reaching a relative residual of 1e-6,
// recomputed on the CPU in double, with a solid block, closed walls or an open top; its
// convergence factor against Jacobi's; and the tolerance mode stopping early.
#include <GL/gl.h>
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/error.h"
#include "fluid/fluid_fields.h"
#include "fluid/multigrid_vcycle.h"
#include "fluid/pressure_jacobi.h"
#include "fluid/pressure_multigrid.h"
#include "fluid/validate.h"
#include "test_util.h"

namespace hf::fluid {
namespace {

constexpr std::uint8_t kOpenTop = 64, kSolid = 128;

struct Cells {
  glm::ivec3 n;
  std::size_t at(const glm::ivec3& c) const { return static_cast<std::size_t>(c.x + n.x * (c.y + n.y * c.z)); }
  std::size_t count() const { return static_cast<std::size_t>(n.x) * n.y * n.z; }
  bool in(const glm::ivec3& c) const { return glm::all(glm::greaterThanEqual(c, glm::ivec3(0))) && glm::all(glm::lessThan(c, n)); }
};

const glm::ivec3 kNeighbour[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

// The neighbour mask classify.comp writes, from a solid predicate (CPU reference).
std::vector<std::uint8_t> neighbourMask(const Cells& g, const std::function<bool(glm::ivec3)>& solid, bool open_top) {
  std::vector<std::uint8_t> m(g.count());
  for (int k = 0; k < g.n.z; ++k)
    for (int j = 0; j < g.n.y; ++j)
      for (int i = 0; i < g.n.x; ++i) {
        const glm::ivec3 c(i, j, k);
        std::uint8_t v = solid(c) ? kSolid : 0;
        for (int d = 0; d < 6; ++d) {
          const glm::ivec3 q = c + kNeighbour[d];
          if (!g.in(q)) {
            if (d == 5 && open_top) v |= kOpenTop;
          } else if (!solid(q)) {
            v |= static_cast<std::uint8_t>(1u << d);
          }
        }
        m[g.at(c)] = v;
      }
  return m;
}

bool fluidCell(std::uint8_t m) { return (m & kSolid) == 0; }

// A x (the operator the solver inverts, A p = -rhs), in double.
std::vector<double> applyA(const Cells& g, const std::vector<std::uint8_t>& m, const std::vector<float>& x) {
  std::vector<double> out(g.count(), 0.0);
  for (int k = 0; k < g.n.z; ++k)
    for (int j = 0; j < g.n.y; ++j)
      for (int i = 0; i < g.n.x; ++i) {
        const glm::ivec3 c(i, j, k);
        const std::uint8_t v = m[g.at(c)];
        if (!fluidCell(v)) continue;
        double a = (v & kOpenTop) ? double(x[g.at(c)]) : 0.0;
        for (int d = 0; d < 6; ++d) {
          if (v & (1u << d)) a += double(x[g.at(c)]) - x[g.at(c + kNeighbour[d])];
        }
        out[g.at(c)] = a;
      }
  return out;
}

// ||rhs - sum_nb (p_nb - p)|| / ||rhs|| over fluid cells, in double.
double relativeResidual(const Cells& g, const std::vector<std::uint8_t>& m, const std::vector<float>& p,
                        const std::vector<float>& rhs) {
  const std::vector<double> ap = applyA(g, m, p);
  double rr = 0.0, bb = 0.0;
  for (std::size_t i = 0; i < g.count(); ++i) {
    if (!fluidCell(m[i])) continue;
    const double r = rhs[i] + ap[i];  // rhs - L p with L = -A
    rr += r * r;
    bb += double(rhs[i]) * rhs[i];
  }
  return std::sqrt(rr / bb);
}

// A smooth rhs with some small-scale content (Pa); zero mean over fluid cells when `compatible`.
std::vector<float> makeRhs(const Cells& g, const std::vector<std::uint8_t>& m, bool compatible) {
  std::vector<float> b(g.count(), 0.0f);
  double sum = 0.0;
  int fluid = 0;
  for (int k = 0; k < g.n.z; ++k)
    for (int j = 0; j < g.n.y; ++j)
      for (int i = 0; i < g.n.x; ++i) {
        const std::size_t n = g.at({i, j, k});
        if (!fluidCell(m[n])) continue;
        b[n] = static_cast<float>(std::sin(0.7 * i + 0.2) * std::cos(0.45 * j) + 0.3 * std::sin(2.9 * k + 1.3 * i) +
                                  0.2 * ((i * 7 + j * 13 + k * 5) % 11) / 11.0);
        sum += b[n];
        ++fluid;
      }
  if (compatible) {
    const float mean = static_cast<float>(sum / fluid);
    for (std::size_t n = 0; n < g.count(); ++n)
      if (fluidCell(m[n])) b[n] -= mean;
  }
  return b;
}

std::vector<float> download(const compute::Texture3D& t) {
  std::vector<float> v(t.texels());
  t.download(v.data(), v.size() * sizeof(float));
  return v;
}

std::vector<float> download4(const compute::Texture3D& t) {
  std::vector<float> v(t.texels() * 4);
  t.download(v.data(), v.size() * sizeof(float));
  return v;
}

std::vector<std::uint8_t> downloadMask(const compute::Texture3D& t) {
  std::vector<std::uint8_t> v(t.texels());
  t.download(v.data(), v.size());
  return v;
}

class Multigrid : public test::DeviceTest {};

TEST(MultigridLevels, HalveRoundingUpForAnyResolution) {
  using V = std::vector<glm::ivec3>;
  EXPECT_EQ(MultigridVCycle::levelResolutions({100, 100, 70}),
            (V{{100, 100, 70}, {50, 50, 35}, {25, 25, 18}, {13, 13, 9}, {7, 7, 5}, {4, 4, 3}}));
  EXPECT_EQ(MultigridVCycle::levelResolutions({128, 128, 128}),
            (V{{128, 128, 128}, {64, 64, 64}, {32, 32, 32}, {16, 16, 16}, {8, 8, 8}, {4, 4, 4}}));
  EXPECT_EQ(MultigridVCycle::levelResolutions({48, 9, 8}), (V{{48, 9, 8}, {24, 5, 4}, {12, 3, 2}, {6, 2, 1}, {3, 1, 1}}));
}

// Fine 7x5x6 (odd on two axes) with a solid wall splitting x = 3 except one gap, an open top.
struct TinyCase {
  Cells fine{{7, 5, 6}};
  Cells coarse{{4, 3, 3}};
  std::vector<std::uint8_t> mask;
  TinyCase() {
    mask = neighbourMask(
        fine, [](glm::ivec3 c) { return (c.x == 3 && !(c.y == 4 && c.z == 5)) || (c.x == 6 && c.y == 0); }, true);
  }
};

// CPU references of mg_coarsen_mask, mg_restrict and mg_prolong.
std::vector<std::uint8_t> coarsenReference(const TinyCase& t) {
  std::vector<std::uint8_t> out(t.coarse.count());
  for (int k = 0; k < t.coarse.n.z; ++k)
    for (int j = 0; j < t.coarse.n.y; ++j)
      for (int i = 0; i < t.coarse.n.x; ++i) {
        const glm::ivec3 C(i, j, k);
        bool fluid = false;
        std::uint8_t v = 0;
        for (int o = 0; o < 8; ++o) {
          const glm::ivec3 off(o & 1, (o >> 1) & 1, (o >> 2) & 1), f = 2 * C + off;
          if (!t.fine.in(f) || !fluidCell(t.mask[t.fine.at(f)])) continue;
          fluid = true;
          const std::uint8_t m = t.mask[t.fine.at(f)];
          v |= m & kOpenTop;
          for (int a = 0; a < 3; ++a) {
            const int side = 2 * a + off[a];  // offset 0: the low side's bit; 1: the high side's
            v |= m & (1u << side);
          }
        }
        out[t.coarse.at(C)] = fluid ? v : kSolid;
      }
  return out;
}

TEST_F(Multigrid, CoarseMaskRestrictionAndProlongationMatchCpuReferences) {
  const TinyCase t;
  std::vector<float> fine_values(t.fine.count()), coarse_values(t.coarse.count()), fine_x(t.fine.count());
  for (std::size_t i = 0; i < fine_values.size(); ++i) {
    fine_values[i] = 0.25f * static_cast<float>((i * 37) % 17) - 2.0f;
    fine_x[i] = 0.5f * static_cast<float>((i * 11) % 7);
  }
  for (std::size_t i = 0; i < coarse_values.size(); ++i) coarse_values[i] = 1.0f + static_cast<float>(i % 5);

  std::vector<std::uint8_t> got_mask;
  std::vector<float> got_restricted, got_prolonged, got_faces;
  // Face fractions (x/y/z faces of one index per texel, res + 1 texels a side): distinct values.
  const glm::ivec3 ffn = t.fine.n + 1;
  std::vector<float> fine_faces(static_cast<std::size_t>(ffn.x) * ffn.y * ffn.z * 4);
  for (std::size_t i = 0; i < fine_faces.size(); ++i) fine_faces[i] = 0.05f * static_cast<float>(i % 17);
  onGl([&] {
    MultigridVCycle v(t.fine.n);
    ASSERT_EQ(v.levels(), 2);
    ASSERT_EQ(v.resolution(1), t.coarse.n);
    compute::Texture3D fm(t.fine.n, compute::TexelFormat::R8UI, "fine mask");
    fm.upload(t.mask.data(), t.mask.size());
    compute::Texture3D fr(t.fine.n, compute::TexelFormat::R32F, "fine residual");
    fr.upload(fine_values.data(), fine_values.size() * sizeof(float));
    compute::Texture3D fx(t.fine.n, compute::TexelFormat::R32F, "fine x");
    fx.upload(fine_x.data(), fine_x.size() * sizeof(float));
    compute::Texture3D cb(t.coarse.n, compute::TexelFormat::R32F, "coarse b");
    compute::Texture3D cx(t.coarse.n, compute::TexelFormat::R32F, "coarse x");
    cx.upload(coarse_values.data(), coarse_values.size() * sizeof(float));
    compute::Texture3D ff(t.fine.n + 1, compute::TexelFormat::RGBA32F, "fine face fractions");
    ff.upload(fine_faces.data(), fine_faces.size() * sizeof(float));
    v.buildMasks(fm, ff, wholeGrid(t.fine.n));
    got_mask = downloadMask(v.mask(1));
    got_faces = download4(v.faces(1));
    v.restrictResidual(t.fine.n, fm, fr, t.coarse.n, cb, 0.5f);
    got_restricted = download(cb);
    v.prolongAdd(t.fine.n, fm, fx, cx);
    got_prolonged = download(fx);
  });

  EXPECT_EQ(got_mask, coarsenReference(t));
  // A coarse face's open fraction is the sum of its (up to four) fine faces' over four; on the
  // far wall of an odd fine size the fine plane is the wall itself. The top z faces (an open
  // top's) also take the ratio of the open top's weight on level 1 to the fine grid's: 4/3.
  const glm::ivec3 cfn = t.coarse.n + 1;
  ASSERT_EQ(got_faces.size(), static_cast<std::size_t>(cfn.x) * cfn.y * cfn.z * 4);
  auto texel = [](const glm::ivec3& size, const glm::ivec3& c) {
    return static_cast<std::size_t>(c.x + size.x * (c.y + size.y * c.z));
  };
  for (int k = 0; k < cfn.z; ++k)
    for (int j = 0; j < cfn.y; ++j)
      for (int i = 0; i < cfn.x; ++i)
        for (int a = 0; a < 3; ++a) {
          const glm::ivec3 C(i, j, k);
          glm::ivec3 face_size = t.coarse.n;
          face_size[a] += 1;
          if (glm::any(glm::greaterThanEqual(C, face_size))) continue;
          const int b = (a + 1) % 3, c = (a + 2) % 3;
          double sum = 0.0;
          for (int o = 0; o < 4; ++o) {
            glm::ivec3 f = 2 * C;
            f[a] = std::min(2 * C[a], t.fine.n[a]);
            f[b] += o & 1;
            f[c] += o >> 1;
            if (f[b] >= t.fine.n[b] || f[c] >= t.fine.n[c]) continue;
            sum += fine_faces[texel(ffn, f) * 4 + static_cast<std::size_t>(a)];
          }
          const double top = (a == 2 && k == t.coarse.n.z) ? 4.0 / 3.0 : 1.0;
          EXPECT_NEAR(got_faces[texel(cfn, C) * 4 + static_cast<std::size_t>(a)], 0.25 * sum * top, 1e-6)
              << "coarse face " << i << " " << j << " " << k << " axis " << a;
        }
  // The gap at (3, 4, 5) links coarse (1, 2, 2) and (2, 2, 2) across x; the wall elsewhere does not.
  EXPECT_TRUE(got_mask[t.coarse.at({1, 2, 2})] & 2u);
  EXPECT_FALSE(got_mask[t.coarse.at({1, 1, 1})] & 2u);
  for (int k = 0; k < t.coarse.n.z; ++k)
    for (int j = 0; j < t.coarse.n.y; ++j)
      for (int i = 0; i < t.coarse.n.x; ++i) {
        const glm::ivec3 C(i, j, k);
        double sum = 0.0;
        for (int o = 0; o < 8; ++o) {
          const glm::ivec3 f = 2 * C + glm::ivec3(o & 1, (o >> 1) & 1, (o >> 2) & 1);
          if (t.fine.in(f) && fluidCell(t.mask[t.fine.at(f)])) sum += fine_values[t.fine.at(f)];
        }
        EXPECT_NEAR(got_restricted[t.coarse.at(C)], 0.5 * sum, 1e-5) << "coarse " << i << " " << j << " " << k;
      }
  for (int k = 0; k < t.fine.n.z; ++k)
    for (int j = 0; j < t.fine.n.y; ++j)
      for (int i = 0; i < t.fine.n.x; ++i) {
        const glm::ivec3 f(i, j, k);
        const float want = fine_x[t.fine.at(f)] + (fluidCell(t.mask[t.fine.at(f)]) ? coarse_values[t.coarse.at(f / 2)] : 0.0f);
        EXPECT_FLOAT_EQ(got_prolonged[t.fine.at(f)], want) << "fine " << i << " " << j << " " << k;
      }
}

// buildMasks over a box of changed fine cells leaves every coarse level as a rebuild of all of it
// would: a fine grid of odd sizes (four levels) gets new masks and face fractions in a box (its
// cells, and their faces: faceBox), near a corner, at the far walls, a single cell, and none.
TEST_F(Multigrid, CoarseLevelsRebuiltInAChangedBoxMatchAWholeRebuild) {
  const glm::ivec3 n(21, 18, 13);
  const glm::ivec3 fn = n + 1;
  const std::size_t cells = static_cast<std::size_t>(n.x) * n.y * n.z;
  const std::size_t faces = static_cast<std::size_t>(fn.x) * fn.y * fn.z;
  std::vector<std::uint8_t> mask(cells);
  std::vector<float> frac(faces * 4);
  std::uint32_t seed = 12345u;
  auto next = [&seed] { return seed = seed * 1664525u + 1013904223u; };
  auto fill = [&](const CellBox& box) {
    for (int k = box.origin.z; k < box.origin.z + box.extent.z; ++k)
      for (int j = box.origin.y; j < box.origin.y + box.extent.y; ++j)
        for (int i = box.origin.x; i < box.origin.x + box.extent.x; ++i)
          mask[static_cast<std::size_t>(i + n.x * (j + n.y * k))] = static_cast<std::uint8_t>(next() >> 24);
    const CellBox fb = faceBox(box, n);
    for (int k = fb.origin.z; k < fb.origin.z + fb.extent.z; ++k)
      for (int j = fb.origin.y; j < fb.origin.y + fb.extent.y; ++j)
        for (int i = fb.origin.x; i < fb.origin.x + fb.extent.x; ++i)
          for (int c = 0; c < 4; ++c) {
            frac[4 * static_cast<std::size_t>(i + fn.x * (j + fn.y * k)) + c] = static_cast<float>(next() >> 8) / 16777216.0f;
          }
  };
  fill(wholeGrid(n));
  const CellBox changes[] = {{{3, 5, 2}, {4, 3, 5}},  {{0, 0, 0}, {2, 1, 3}}, {{17, 14, 9}, {4, 4, 4}},
                             {{20, 17, 12}, {1, 1, 1}}, {{7, 8, 6}, {1, 1, 1}}, {{4, 4, 4}, {0, 3, 3}}};
  onGl([&] {
    MultigridVCycle kept(n);
    ASSERT_EQ(kept.levels(), 4);
    compute::Texture3D fm(n, compute::TexelFormat::R8UI, "fine mask");
    compute::Texture3D ff(fn, compute::TexelFormat::RGBA32F, "fine face fractions");
    fm.upload(mask.data(), mask.size());
    ff.upload(frac.data(), frac.size() * sizeof(float));
    kept.buildMasks(fm, ff, wholeGrid(n));
    for (const CellBox& box : changes) {
      fill(box);
      fm.upload(mask.data(), mask.size());
      ff.upload(frac.data(), frac.size() * sizeof(float));
      kept.buildMasks(fm, ff, box);
      MultigridVCycle whole(n);
      whole.buildMasks(fm, ff, wholeGrid(n));
      for (int l = 1; l < kept.levels(); ++l) {
        EXPECT_EQ(downloadMask(kept.mask(l)), downloadMask(whole.mask(l)))
            << "level " << l << " after a change at " << box.origin.x << " " << box.origin.y << " " << box.origin.z;
        EXPECT_EQ(download4(kept.faces(l)), download4(whole.faces(l)))
            << "level " << l << " after a change at " << box.origin.x << " " << box.origin.y << " " << box.origin.z;
      }
    }
  });
}

// One solve on a fresh FluidFields with the given mask and rhs; returns the stats and pressure.
struct Solved {
  SolveStats stats;
  std::vector<float> pressure;
};

Solved solveOnce(PressureSolver& solver, FluidFields& f, const std::vector<std::uint8_t>& mask,
                 const std::vector<float>& rhs, const FluidParams& params) {
  f.nbmask.upload(mask.data(), mask.size());
  // Every face open: the mask's links alone say which neighbours the operator couples.
  const std::vector<float> open(f.face_open.texels() * 4, 1.0f);
  f.face_open.upload(open.data(), open.size() * sizeof(float));
  f.rhs.upload(rhs.data(), rhs.size() * sizeof(float));
  f.pressure.cur().clear();
  solver.obstacleChanged(wholeGrid(f.nbmask.size()));
  Solved s;
  s.stats = solver.solve(f, params);
  s.pressure = download(f.pressure.cur());
  return s;
}

// solveOnce by a new PressureMultigrid on new fields of `g`'s size, on the device.
Solved solveMultigridOnce(const Cells& g, const std::vector<std::uint8_t>& mask, const std::vector<float>& rhs,
                          const FluidParams& params) {
  return Multigrid::onGl([&] {
    Grid grid;
    grid.res = g.n;
    FluidFields f(grid);
    PressureMultigrid mg(grid);
    return solveOnce(mg, f, mask, rhs, params);
  });
}

struct SolveCase {
  const char* name;
  glm::ivec3 res;
  bool open_top;
};

class MultigridSolve : public Multigrid, public ::testing::WithParamInterface<SolveCase> {};

// A solid block off centre. The rhs has zero mean over the fluid, as a divergence has (a closed
// box needs it; with an open top a large mean would make the pressure ~n^2 times larger than
// the rhs, and float32 pressure then floors the residual at a few 1e-6).
TEST_P(MultigridSolve, ReachesOneMillionthWithASolidBlock) {
  const SolveCase sc = GetParam();
  const Cells g{sc.res};
  const auto mask = neighbourMask(
      g, [&](glm::ivec3 c) { return c.x >= 3 && c.x < 7 && c.y >= 4 && c.y < 9 && c.z >= 2 && c.z < 5; }, sc.open_top);
  const auto rhs = makeRhs(g, mask, true);
  FluidParams params;
  params.open_top = sc.open_top;
  params.pressure_solver = PressureSolverKind::Multigrid;
  params.pressure_tolerance = 1e-6f;
  params.pressure_iterations = 60;
  const Solved s = solveMultigridOnce(g, mask, rhs, params);
  const double cpu = relativeResidual(g, mask, s.pressure, rhs);
  EXPECT_LE(s.stats.relative_residual, 1e-6f);
  EXPECT_LE(cpu, 1.2e-6) << "recomputed in double";
  EXPECT_GT(s.stats.iterations, 0);
  EXPECT_LT(s.stats.iterations, 30) << "CG with a V-cycle needs tens of iterations at most";
  EXPECT_NEAR(s.stats.initial_relative_residual, 1.0f, 1e-5f) << "cold start: r = rhs";
  for (std::size_t i = 0; i < g.count(); ++i) {
    if (!fluidCell(mask[i])) {
      EXPECT_EQ(s.pressure[i], 0.0f) << "solid cells hold 0";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Grids, MultigridSolve,
                         ::testing::Values(SolveCase{"ClosedCube16", {16, 16, 16}, false},
                                           SolveCase{"OpenTopCube16", {16, 16, 16}, true},
                                           SolveCase{"ClosedOdd13x11x9", {13, 11, 9}, false},
                                           SolveCase{"OpenTopOdd21x12x10", {21, 12, 10}, true},
                                           // At least MultigridVCycle::kLargeGridCells: three sweeps a side.
                                           SolveCase{"ClosedLarge44x41x37", {44, 41, 37}, false}),
                         [](const auto& info) { return std::string(info.param.name); });

// Fixed-count mode on a 24^3 open box: the mean convergence factor per CG iteration (one
// V-cycle) is far below Jacobi's per sweep (close to 1, 1 - O(1/n^2)), and below even Jacobi's
// over as many sweeps as one iteration costs in work (about 10), by far.
TEST_F(Multigrid, ConvergenceFactorPerCycleIsFarBelowJacobis) {
  const Cells g{{24, 24, 24}};
  const auto mask = neighbourMask(g, [](glm::ivec3 c) { return glm::length(glm::vec3(c) - glm::vec3(11.5f, 12.5f, 10.5f)) < 5.0f; }, true);
  const auto rhs = makeRhs(g, mask, false);
  FluidParams params;
  params.open_top = true;
  constexpr int kCycles = 4, kSweeps = 200;
  const auto [mg, jac] = onGl([&] {
    Grid grid;
    grid.res = g.n;
    FluidFields f(grid);
    PressureMultigrid m(grid);
    PressureJacobi j(grid);
    params.pressure_iterations = kCycles;
    const Solved a = solveOnce(m, f, mask, rhs, params);
    params.pressure_iterations = kSweeps;
    const Solved b = solveOnce(j, f, mask, rhs, params);
    return std::make_pair(a, b);
  });
  EXPECT_EQ(mg.stats.iterations, kCycles);
  EXPECT_EQ(jac.stats.iterations, kSweeps);
  const double mg_factor = std::pow(relativeResidual(g, mask, mg.pressure, rhs), 1.0 / kCycles);
  const double jacobi_factor = std::pow(relativeResidual(g, mask, jac.pressure, rhs), 1.0 / kSweeps);
  EXPECT_LT(mg_factor, 0.3) << "multigrid CG, per iteration";
  EXPECT_GT(jacobi_factor, 0.95) << "Jacobi, per sweep";
  EXPECT_LT(mg_factor, std::pow(jacobi_factor, 10.0) * 0.5) << "multigrid " << mg_factor << ", Jacobi " << jacobi_factor;
}

// The open top's weight on the coarse levels (MultigridVCycle::openTopWeight) puts its zero where
// the fine grid's is, half a fine cell above the top face: 1 on the fine grid, 4/3 on level 1,
// then towards 2. With the fine grid's 1 on every level an open box converged much slower than
// the same box closed (24^3, a sphere: 0.129 per CG iteration against 0.082); now about as fast
// (0.087).
TEST_F(Multigrid, AnOpenTopConvergesAboutAsFastAsAClosedBox) {
  EXPECT_FLOAT_EQ(MultigridVCycle::openTopWeight(0), 1.0f);
  EXPECT_FLOAT_EQ(MultigridVCycle::openTopWeight(1), 4.0f / 3.0f);
  EXPECT_FLOAT_EQ(MultigridVCycle::openTopWeight(2), 1.6f);
  EXPECT_LT(MultigridVCycle::openTopWeight(8), 2.0f);
  const Cells g{{24, 24, 24}};
  auto sphere = [](glm::ivec3 c) { return glm::length(glm::vec3(c) - glm::vec3(11.5f, 12.5f, 10.5f)) < 5.0f; };
  constexpr int kCycles = 4;
  double factor[2] = {0.0, 0.0};
  for (bool open_top : {false, true}) {
    const auto mask = neighbourMask(g, sphere, open_top);
    const auto rhs = makeRhs(g, mask, true);
    FluidParams params;
    params.open_top = open_top;
    params.pressure_iterations = kCycles;
    const Solved s = solveMultigridOnce(g, mask, rhs, params);
    factor[open_top ? 1 : 0] = std::pow(relativeResidual(g, mask, s.pressure, rhs), 1.0 / kCycles);
  }
  std::printf("per CG iteration: closed %.4f, open top %.4f\n", factor[0], factor[1]);
  EXPECT_LT(factor[1], 1.2 * factor[0]) << "open top " << factor[1] << ", closed " << factor[0];
}

// Tolerance mode stops at the first iteration that reaches the tolerance and says how many it
// ran; one iteration fewer (fixed count) is not enough. Jacobi's does the same in its checks.
TEST_F(Multigrid, ToleranceModeStopsEarlyAndReportsIterations) {
  const Cells g{{20, 18, 16}};
  const auto mask = neighbourMask(g, [](glm::ivec3 c) { return c.x > 8 && c.x < 12 && c.y > 6 && c.z < 9; }, false);
  const auto rhs = makeRhs(g, mask, true);
  FluidParams params;
  params.pressure_tolerance = 1e-3f;
  params.pressure_iterations = 50;
  const auto results = onGl([&] {
    Grid grid;
    grid.res = g.n;
    FluidFields f(grid);
    PressureMultigrid m(grid);
    PressureJacobi j(grid);
    std::vector<Solved> out;
    out.push_back(solveOnce(m, f, mask, rhs, params));
    FluidParams fixed = params;
    fixed.pressure_tolerance = 0.0f;
    fixed.pressure_iterations = std::max(1, out[0].stats.iterations - 1);
    out.push_back(solveOnce(m, f, mask, rhs, fixed));
    FluidParams jp = params;
    jp.pressure_tolerance = 0.05f;
    jp.pressure_iterations = 5000;
    out.push_back(solveOnce(j, f, mask, rhs, jp));
    return out;
  });
  const Solved& tol = results[0];
  EXPECT_GT(tol.stats.iterations, 1);
  EXPECT_LT(tol.stats.iterations, 50) << "stopped before the cap";
  EXPECT_LE(tol.stats.relative_residual, 1e-3f);
  EXPECT_NEAR(relativeResidual(g, mask, tol.pressure, rhs), tol.stats.relative_residual, 1e-5);
  EXPECT_GT(relativeResidual(g, mask, results[1].pressure, rhs), 1e-3) << "one iteration fewer is not enough";
  const Solved& jac = results[2];
  EXPECT_GT(jac.stats.iterations, 0);
  EXPECT_LT(jac.stats.iterations, 5000);
  EXPECT_EQ(jac.stats.iterations % PressureJacobi::kCheckInterval, 0);
  EXPECT_LE(jac.stats.relative_residual, 0.05f);
  EXPECT_NEAR(relativeResidual(g, mask, jac.pressure, rhs), jac.stats.relative_residual, 1e-4);
}

TEST(MultigridSettings, ToleranceOutsideItsRangeIsRejected) {
  for (float bad : {-1e-3f, 1e-9f, 1.0f, 2.0f, NAN, INFINITY}) {
    FluidParams p;
    p.pressure_tolerance = bad;
    try {
      validate(p);
      ADD_FAILURE() << "tolerance " << bad << " accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_TRUE(test::contains(e.what(), "pressure tolerance")) << e.what();
    }
  }
  FluidParams ok;
  for (float good : {0.0f, kMinPressureTolerance, 1e-4f, 0.5f}) {
    ok.pressure_tolerance = good;
    EXPECT_NO_THROW(validate(ok)) << good;
  }
}

}  // namespace
}  // namespace hf::fluid
