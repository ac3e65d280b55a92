// SPDX-License-Identifier: GPL-3.0-or-later
// The V-cycle's fused stages (issue 20) against the separate stages they replace, on odd grids
// with a solid block, an open top and cut-cell face fractions: the coarsest solve in one
// dispatch (mg_coarsest) against 4 x kCoarsestSweeps mg_smooth dispatches, the residual and the
// restriction in one pass (mg_residual_restrict) against mg_residual + mg_restrict, and the
// prolongation folded into the first post-smoothing sweep (mg_smooth with PROLONG) against
// mg_prolong + two sweeps. The same arithmetic in each: equal to float rounding (measured: equal
// to the bit on llvmpipe; the bound allows a compiler's different contraction). And a sweep over
// rows that are wholly open inside against the cell formula on the host. And a red-black pair of
// sweeps in one pass (dispatchSeries: on the CPU a plane apart, in slabs of planes on several threads)
// against the two dispatches, to the bit.
#include <GL/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "compute/compute_program.h"
#include "compute/workgroup.h"
#include "cpu/cpu_device.h"
#include "cpu/kernel.h"
#include "fluid/fluid_fields.h"
#include "fluid/multigrid_vcycle.h"
#include "test_util.h"

namespace hf::fluid {
namespace {

constexpr std::uint8_t kOpenTop = 64, kSolid = 128;
const glm::ivec3 kNb[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

std::size_t at(const glm::ivec3& n, const glm::ivec3& c) { return static_cast<std::size_t>(c.x + n.x * (c.y + n.y * c.z)); }
std::size_t count(const glm::ivec3& n) { return static_cast<std::size_t>(n.x) * n.y * n.z; }
bool inside(const glm::ivec3& n, const glm::ivec3& c) {
  return glm::all(glm::greaterThanEqual(c, glm::ivec3(0))) && glm::all(glm::lessThan(c, n));
}

// classify.comp's neighbour mask for a block of solid cells, open top.
std::vector<std::uint8_t> maskWithBlock(const glm::ivec3& n, const glm::ivec3& lo, const glm::ivec3& hi) {
  auto solid = [&](glm::ivec3 c) { return glm::all(glm::greaterThanEqual(c, lo)) && glm::all(glm::lessThan(c, hi)); };
  std::vector<std::uint8_t> m(count(n));
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        const glm::ivec3 c(i, j, k);
        std::uint8_t v = solid(c) ? kSolid : 0;
        for (int d = 0; d < 6; ++d) {
          const glm::ivec3 q = c + kNb[d];
          if (!inside(n, q)) {
            if (d == 5) v |= kOpenTop;
          } else if (!solid(q) && !solid(c)) {
            v |= static_cast<std::uint8_t>(1u << d);
          }
        }
        m[at(n, c)] = v;
      }
  return m;
}

std::vector<float> values(std::size_t n, int a, int b, float scale, float offset) {
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = scale * static_cast<float>((i * a) % b) + offset;
  return v;
}

// Face fractions 0.4-0.96 (cut cells), RGBA32F of (n + 1) texels.
std::vector<float> faceFractions(const glm::ivec3& n) { return values(count(n + 1) * 4, 7, 15, 0.04f, 0.4f); }

struct Level {
  Level(const glm::ivec3& res, const std::vector<std::uint8_t>& m)
      : mask(res, compute::TexelFormat::R8UI, "mask"),
        faces(res + 1, compute::TexelFormat::RGBA32F, "faces"),
        x(res, compute::TexelFormat::R32F, "x"),
        b(res, compute::TexelFormat::R32F, "b") {
    mask.upload(m.data(), m.size());
    const std::vector<float> f = faceFractions(res);
    faces.upload(f.data(), f.size() * sizeof(float));
    const std::vector<float> bv = values(count(res), 13, 17, 0.3f, -2.4f);
    b.upload(bv.data(), bv.size() * sizeof(float));
  }
  void setX(const std::vector<float>& v) { x.upload(v.data(), v.size() * sizeof(float)); }
  compute::Texture3D mask, faces, x, b;
};

std::vector<float> download(const compute::Texture3D& t) {
  std::vector<float> v(t.texels());
  t.download(v.data(), v.size() * sizeof(float));
  return v;
}

// Largest |a - b| over the largest |a|; and whether every value is equal to the bit.
struct Diff {
  double rel = 0.0;
  bool exact = true;
};
Diff compare(const std::vector<float>& a, const std::vector<float>& b) {
  Diff d;
  double scale = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    scale = std::max(scale, double(std::fabs(a[i])));
    worst = std::max(worst, double(std::fabs(a[i] - b[i])));
    d.exact = d.exact && a[i] == b[i];
  }
  d.rel = scale > 0.0 ? worst / scale : worst;
  return d;
}

class MultigridFused : public test::DeviceTest {};

TEST_F(MultigridFused, CoarsestSolveInOneDispatchEqualsTheSweeps) {
  const glm::ivec3 n(4, 4, 3);  // a coarsest level of 100x100x70
  const auto m = maskWithBlock(n, {1, 1, 1}, {2, 3, 2});
  std::vector<float> fused, swept, b_before, b_after;
  onGl([&] {
    MultigridVCycle v(n);
    Level one(n, m), two(n, m);
    one.setX(values(count(n), 5, 9, 1.0f, 3.0f));  // stale values: the solve starts from x = 0
    two.setX(values(count(n), 5, 9, 1.0f, 3.0f));
    b_before = download(one.b);
    v.solveCoarsest(n, one.mask, one.faces, one.x, one.b);
    for (int s = 0; s < MultigridVCycle::kCoarsestSweeps; ++s) {
      v.smooth(n, two.mask, two.faces, two.x, two.b, 0, s == 0);
      v.smooth(n, two.mask, two.faces, two.x, two.b, 1, false);
    }
    for (int s = 0; s < MultigridVCycle::kCoarsestSweeps; ++s) {
      v.smooth(n, two.mask, two.faces, two.x, two.b, 1, false);
      v.smooth(n, two.mask, two.faces, two.x, two.b, 0, false);
    }
    fused = download(one.x);
    swept = download(two.x);
    b_after = download(one.b);
  });
  const Diff d = compare(swept, fused);
  EXPECT_LE(d.rel, 1e-6) << "exact: " << d.exact;
  EXPECT_EQ(b_before, b_after);
  double largest = 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m[i] & kSolid) {
      EXPECT_EQ(fused[i], 0.0f) << "solid cells hold 0";
    }
    largest = std::max(largest, double(std::fabs(fused[i])));
  }
  EXPECT_GT(largest, 0.1) << "the solve did something";
}

TEST_F(MultigridFused, ResidualRestrictEqualsResidualThenRestrict) {
  const glm::ivec3 fine(9, 7, 6), coarse(5, 4, 3);
  const auto m = maskWithBlock(fine, {3, 2, 1}, {5, 5, 4});
  std::vector<float> fused, separate;
  onGl([&] {
    MultigridVCycle v(fine);
    ASSERT_EQ(v.resolution(1), coarse);
    Level f(fine, m);
    f.setX(values(count(fine), 11, 13, 0.7f, -4.0f));
    compute::Texture3D res(fine, compute::TexelFormat::R32F, "fine residual");
    compute::Texture3D cb1(coarse, compute::TexelFormat::R32F, "coarse b fused");
    compute::Texture3D cb2(coarse, compute::TexelFormat::R32F, "coarse b separate");
    v.residualRestrict(fine, f.mask, f.faces, f.x, f.b, coarse, cb1, MultigridVCycle::kCoarseScale);
    v.residual(fine, f.mask, f.faces, f.x, f.b, res);
    v.restrictResidual(fine, f.mask, res, coarse, cb2, MultigridVCycle::kCoarseScale);
    fused = download(cb1);
    separate = download(cb2);
  });
  const Diff d = compare(separate, fused);
  EXPECT_LE(d.rel, 1e-6) << "exact: " << d.exact;
  EXPECT_GT(*std::max_element(separate.begin(), separate.end()), 0.1f);
}

TEST_F(MultigridFused, ProlongFoldedIntoTheFirstSweepEqualsProlongThenSweeps) {
  const glm::ivec3 fine(9, 7, 6), coarse(5, 4, 3);
  const auto m = maskWithBlock(fine, {3, 2, 1}, {5, 5, 4});
  std::vector<float> fused, separate;
  onGl([&] {
    MultigridVCycle v(fine);
    Level one(fine, m), two(fine, m);
    const std::vector<float> x0 = values(count(fine), 11, 13, 0.7f, -4.0f);
    one.setX(x0);
    two.setX(x0);
    compute::Texture3D cx(coarse, compute::TexelFormat::R32F, "coarse x");
    const std::vector<float> c = values(count(coarse), 3, 7, 0.9f, -1.5f);
    cx.upload(c.data(), c.size() * sizeof(float));
    v.smoothProlonged(fine, one.mask, one.faces, one.x, one.b, cx, 1);
    v.smooth(fine, one.mask, one.faces, one.x, one.b, 0, false);
    v.prolongAdd(fine, two.mask, two.x, cx);
    v.smooth(fine, two.mask, two.faces, two.x, two.b, 1, false);
    v.smooth(fine, two.mask, two.faces, two.x, two.b, 0, false);
    fused = download(one.x);
    separate = download(two.x);
  });
  const Diff d = compare(separate, fused);
  EXPECT_LE(d.rel, 1e-6) << "exact: " << d.exact;
}

// The sweep's arithmetic on the host, in mg_smooth.comp's order: one colour of a red-black sweep of
// x in place (the other colour read), over faces (RGBA32F, (n + 1) texels, x fastest, channels
// together) and b.
void hostSweep(const glm::ivec3& n, const std::vector<std::uint8_t>& m, const std::vector<float>& faces,
               const std::vector<float>& b, int colour, std::vector<float>& x) {
  const glm::ivec3 fn = n + 1;
  auto face = [&](const glm::ivec3& c, int axis) { return faces[4 * at(fn, c) + static_cast<std::size_t>(axis)]; };
  auto xat = [&](const glm::ivec3& c) { return inside(n, c) ? x[at(n, c)] : 0.0f; };
  for (int k = 0; k < n.z; ++k)
    for (int j = 0; j < n.y; ++j)
      for (int i = 0; i < n.x; ++i) {
        if (((i + j + k) & 1) != colour) continue;
        const glm::ivec3 c(i, j, k);
        const unsigned mc = m[at(n, c)];
        const float w[6] = {face(c, 0), face(c + glm::ivec3(1, 0, 0), 0), face(c, 1),
                            face(c + glm::ivec3(0, 1, 0), 1), face(c, 2), face(c + glm::ivec3(0, 0, 1), 2)};
        float nsum = (mc & kOpenTop) != 0 ? w[5] : 0.0f;
        for (int d = 0; d < 6; ++d) nsum += ((mc >> d) & 1u) != 0 ? w[d] : 0.0f;
        float sum = 0.0f;
        for (int d = 0; d < 6; ++d) sum += ((mc >> d) & 1u) != 0 ? w[d] * xat(c + kNb[d]) : 0.0f;
        x[at(n, c)] = ((mc & kSolid) != 0 || nsum == 0.0f) ? 0.0f : (b[at(n, c)] + sum) / nsum;
      }
}

// Most rows of a real grid are wholly open inside (the CPU backend's sweep takes those rows with
// the mask and fractions as constants, cpu/kernels/mg_smooth.cpp): on a grid with such rows beside
// rows with a solid block, cut faces and the open top, a sweep of each colour equals the host's
// arithmetic, to the bit on the CPU backend; and a changed face (a new upload) is seen at once.
TEST_F(MultigridFused, SweepsOverOpenRowsEqualTheCellFormula) {
  const glm::ivec3 n(21, 9, 8);
  const auto m = maskWithBlock(n, {6, 5, 2}, {9, 7, 4});
  std::vector<float> faces(count(n + 1) * 4, 1.0f);
  for (std::size_t t = 0; t < count(n + 1); ++t) {
    const glm::ivec3 c(static_cast<int>(t % (n.x + 1)), static_cast<int>(t / (n.x + 1) % (n.y + 1)),
                       static_cast<int>(t / ((n.x + 1) * (n.y + 1))));
    if (c.y == 2) faces[4 * t + 1] = 0.5f + 0.01f * static_cast<float>(c.x);  // a row of cut y-faces
  }
  const std::vector<float> b = values(count(n), 13, 17, 0.3f, -2.4f);
  std::vector<float> host = values(count(n), 11, 13, 0.7f, -4.0f);
  std::vector<float> device_after_first, device_after_second;
  std::vector<float> faces_cut = faces;
  faces_cut[4 * at(n + 1, glm::ivec3(10, 4, 6)) + 0] = 0.25f;  // a cut x-face in an open row
  onGl([&] {
    MultigridVCycle v(n);
    Level l(n, m);
    l.faces.upload(faces.data(), faces.size() * sizeof(float));
    l.b.upload(b.data(), b.size() * sizeof(float));
    l.setX(host);
    v.smooth(n, l.mask, l.faces, l.x, l.b, 0, false);
    v.smooth(n, l.mask, l.faces, l.x, l.b, 1, false);
    device_after_first = download(l.x);
    l.faces.upload(faces_cut.data(), faces_cut.size() * sizeof(float));
    v.smooth(n, l.mask, l.faces, l.x, l.b, 0, false);
    v.smooth(n, l.mask, l.faces, l.x, l.b, 1, false);
    device_after_second = download(l.x);
  });
  hostSweep(n, m, faces, b, 0, host);
  hostSweep(n, m, faces, b, 1, host);
  Diff d = compare(host, device_after_first);
  if (test::testOnCpu()) {
    EXPECT_TRUE(d.exact) << "relative difference " << d.rel;
  } else {
    EXPECT_LE(d.rel, 1e-6);
  }
  hostSweep(n, m, faces_cut, b, 0, host);
  hostSweep(n, m, faces_cut, b, 1, host);
  d = compare(host, device_after_second);
  if (test::testOnCpu()) {
    EXPECT_TRUE(d.exact) << "relative difference " << d.rel;
  } else {
    EXPECT_LE(d.rel, 1e-6);
  }
  EXPECT_GT(*std::max_element(host.begin(), host.end()), 0.1f);
}

// Series of red-black sweeps through dispatchSeries (the CPU runs them in one pass, each a plane
// behind the one before, in slabs of planes on several threads) against the separate dispatches:
// the same bits, on 1, 2 and 4 threads (4 slabs of a grid big enough to be cut), for two and
// four sweeps, before a correction (red from the zero guess first) and after it (black with the
// coarse correction folded in first), with a solid block, an open top and cut faces.
TEST(MultigridSweepSeries, InOnePassEqualTheSweepsToTheBit) {
  const glm::ivec3 n(37, 29, 67);  // 72k cells, 67 planes
  static_assert(37LL * 29 * 67 >= cpu::kSerialInvocations, "a grid the CPU cuts into slabs");
  const glm::ivec3 coarse = (n + 1) / 2;
  const auto m = maskWithBlock(n, {9, 7, 12}, {20, 15, 23});
  const std::vector<float> x0 = values(count(n), 11, 23, 0.25f, -2.0f);
  const std::vector<float> cx = values(count(coarse), 5, 19, 0.1f, -0.7f);
  const glm::ivec3 invocations((n.x + 1) / 2, n.y, n.z);
  std::map<std::pair<int, int>, std::vector<float>> reference;  // (sweeps, side) -> one thread's
  for (int threads : {1, 2, 4}) {
    cpu::CpuWorker worker(threads);
    worker.call([&] {
      compute::Defines prolong = compute::cellGroupDefines();
      prolong.emplace_back("PROLONG", "1");
      compute::ComputeProgram plain("mg_smooth.comp", compute::cellGroupDefines());
      compute::ComputeProgram with_prolong("mg_smooth.comp", prolong);
      std::vector<std::unique_ptr<compute::ComputeProgram>> rest;
      for (int i = 0; i < 3; ++i) rest.push_back(std::make_unique<compute::ComputeProgram>("mg_smooth.comp", compute::cellGroupDefines()));
      Level l(n, m);
      compute::Texture3D coarse_x(coarse, compute::TexelFormat::R32F, "coarse x");
      coarse_x.upload(cx.data(), cx.size() * sizeof(float));
      for (int sweeps : {2, 4}) {
        for (int side = 0; side < 2; ++side) {  // 0: red (zero guess) first; 1: black (PROLONG) first
          std::vector<std::pair<compute::ComputeProgram*, glm::ivec3>> series;
          series.emplace_back(side == 0 ? &plain : &with_prolong, invocations);
          for (int i = 1; i < sweeps; ++i) series.emplace_back(rest[static_cast<std::size_t>(i - 1)].get(), invocations);
          std::vector<float> result[2];
          for (int fused = 0; fused < 2; ++fused) {
            l.setX(x0);
            l.faces.bindImage(kFaceOpenUnit, compute::Access::Read);
            l.x.bindImage(0, compute::Access::ReadWrite);
            l.b.bindImage(1, compute::Access::Read);
            l.mask.bindImage(2, compute::Access::Read);
            coarse_x.bindImage(3, compute::Access::Read);
            for (std::size_t i = 0; i < series.size(); ++i) {
              compute::ComputeProgram& p = *series[i].first;
              p.set("u_res", n);
              p.set("u_colour", (side + static_cast<int>(i)) % 2);
              p.set("u_zero_guess", side == 0 && i == 0 ? 1 : 0);
            }
            if (fused) {
              compute::ComputeProgram::dispatchSeries(series);
            } else {
              for (const auto& [p, inv] : series) p->dispatch(inv);
            }
            result[fused] = download(l.x);
          }
          const std::string what = std::to_string(sweeps) + " sweeps, side " + std::to_string(side) + ", " +
                                   std::to_string(threads) + " threads";
          EXPECT_TRUE(result[0] == result[1]) << what << ": relative difference " << compare(result[0], result[1]).rel;
          EXPECT_FALSE(result[0] == x0) << what << ": the sweeps changed nothing";
          auto& ref = reference[{sweeps, side}];
          if (threads == 1) {
            ref = result[1];
          } else {
            EXPECT_TRUE(ref == result[1]) << what << " against one thread";
          }
        }
      }
    });
  }
}

}  // namespace
}  // namespace hf::fluid
