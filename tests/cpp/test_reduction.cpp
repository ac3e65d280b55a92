// SPDX-License-Identifier: GPL-3.0-or-later
// The two-level GPU reductions: GroupReducer sums partials exactly for counts that are not
// multiples of its 256-wide workgroup, and ForceReducer's surface sum gives the known
// answers of closed voxel surfaces (zero net force of a uniform pressure, -rho g V of a
// hydrostatic one, the exact count of exposed faces).
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/error.h"
#include "fluid/grid.h"
#include "force/force_reducer.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"
#include "compute/texture3d.h"
#include "compute/workgroup.h"
#include "obstacle/cell_class.h"
#include "obstacle/classifier.h"
#include "test_util.h"

namespace hf {
namespace {

using compute::ComputeProgram;
using compute::GroupReducer;

// partials[i] = (1, i, i % 7, -0.5) for i < n, then `fill` in every entry up to `total`.
void fillPartials(GroupReducer& reducer, std::size_t n, std::size_t total, float fill) {
  std::vector<glm::vec4> p(total, glm::vec4(fill));
  for (std::size_t i = 0; i < n; ++i) p[i] = glm::vec4(1.0f, static_cast<float>(i), static_cast<float>(i % 7), -0.5f);
  reducer.partials().upload(p.data(), p.size() * sizeof(glm::vec4));
}

glm::dvec4 expectedSum(std::size_t n) {
  glm::dvec4 s(0.0);
  for (std::size_t i = 0; i < n; ++i) s += glm::dvec4(1.0, double(i), double(i % 7), -0.5);
  return s;
}

class ReductionTest : public test::DeviceTest {};

TEST_F(ReductionTest, GroupReducerSumsExactlyForAnyCount) {
  constexpr std::size_t kMax = 5000;
  const std::vector<std::size_t> counts = {1, 2, 255, 256, 257, 511, 1000, 4097, kMax};
  const std::vector<glm::vec4> got = onGl([&] {
    GroupReducer reducer(kMax, 2);
    EXPECT_EQ(reducer.maxGroups(), kMax);
    std::vector<glm::vec4> out;
    for (std::size_t n : counts) {
      // Garbage in every partial past n: those entries must not be summed.
      fillPartials(reducer, n, kMax, 1.0e6f);
      reducer.reduce(n, n % 2);
      out.push_back(reducer.readResults()[n % 2]);
    }
    return out;
  });
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const std::size_t n = counts[k];
    const glm::dvec4 want = expectedSum(n);  // every partial sum is an integer below 2^24: exact
    EXPECT_EQ(got[k].x, static_cast<float>(want.x)) << "count " << n;
    EXPECT_EQ(got[k].y, static_cast<float>(want.y)) << "count " << n;
    EXPECT_EQ(got[k].z, static_cast<float>(want.z)) << "count " << n;
    EXPECT_EQ(got[k].w, static_cast<float>(want.w)) << "count " << n;
  }
}

TEST_F(ReductionTest, GroupReducerSlotsAreIndependentAndClearable) {
  const auto results = onGl([] {
    GroupReducer reducer(300, 3);
    fillPartials(reducer, 300, 300, 0.0f);
    std::vector<std::vector<glm::vec4>> r;
    r.push_back(reducer.readResults());  // nothing reduced yet
    reducer.reduce(300, 2);
    reducer.reduce(10, 0);
    reducer.reduce(0, 1);  // an empty sum is zero
    r.push_back(reducer.readResults());
    reducer.clearResults();
    r.push_back(reducer.readResults());
    EXPECT_THROW(reducer.reduce(301, 0), Error);
    EXPECT_THROW(reducer.reduce(1, 3), Error);
    return r;
  });
  ASSERT_EQ(results.size(), 3u);
  for (const auto& v : results) ASSERT_EQ(v.size(), 3u);
  for (int s = 0; s < 3; ++s) EXPECT_EQ(results[0][s], glm::vec4(0.0f)) << "slot " << s;
  EXPECT_EQ(results[1][0], glm::vec4(expectedSum(10)));
  EXPECT_EQ(results[1][1], glm::vec4(0.0f));
  EXPECT_EQ(results[1][2], glm::vec4(expectedSum(300)));
  for (int s = 0; s < 3; ++s) EXPECT_EQ(results[2][s], glm::vec4(0.0f)) << "slot " << s;
}

// ---- ForceReducer on hand-made solids -------------------------------------------------------

struct Shape {
  glm::ivec3 res;
  std::vector<std::uint8_t> solid;  // x fastest
  std::size_t idx(int i, int j, int k) const {
    return static_cast<std::size_t>(i + res.x * (j + res.y * k));
  }
  bool at(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= res.x || j >= res.y || k >= res.z) return false;
    return solid[idx(i, j, k)] != 0;
  }
  std::size_t count() const {
    std::size_t n = 0;
    for (auto v : solid) n += v != 0;
    return n;
  }
  // Faces between a solid cell and a fluid cell inside the grid.
  int exposedFaces() const {
    static const int nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    int n = 0;
    for (int k = 0; k < res.z; ++k)
      for (int j = 0; j < res.y; ++j)
        for (int i = 0; i < res.x; ++i) {
          if (!at(i, j, k)) continue;
          for (const auto& d : nb) {
            const int a = i + d[0], b = j + d[1], c = k + d[2];
            const bool in = a >= 0 && b >= 0 && c >= 0 && a < res.x && b < res.y && c < res.z;
            if (in && !at(a, b, c)) ++n;
          }
        }
    return n;
  }
};

// A 4x5x6 box with a 2x2x2 fluid cavity inside it, plus a separate L-shaped piece.
Shape makeShape() {
  Shape s;
  s.res = glm::ivec3(16, 16, 16);
  s.solid.assign(16 * 16 * 16, 0);
  for (int k = 3; k < 9; ++k)
    for (int j = 2; j < 7; ++j)
      for (int i = 2; i < 6; ++i) s.solid[s.idx(i, j, k)] = 1;
  for (int k = 5; k < 7; ++k)
    for (int j = 3; j < 5; ++j)
      for (int i = 3; i < 5; ++i) s.solid[s.idx(i, j, k)] = 0;  // sealed cavity
  for (int i = 9; i < 14; ++i) s.solid[s.idx(i, 11, 10)] = 1;
  for (int k = 10; k < 14; ++k) s.solid[s.idx(9, 11, k)] = 1;
  return s;
}

struct ForceCase {
  std::function<float(int, int, int)> pressure;  // dynamic pressure per cell (Pa)
  glm::vec3 rho_g;
  glm::vec3 reference_m;
  obstacle::CellBox box;
};

std::vector<force::BodyForce> runForce(const Shape& shape, const fluid::Grid& grid, const std::vector<ForceCase>& cases) {
  return test::DeviceTest::onGl([&] {
    compute::Texture3D solid(grid.res, compute::TexelFormat::R8UI, "solid");
    compute::Texture3D cls(grid.res, compute::TexelFormat::R8UI, "classes");
    compute::Texture3D nbmask(grid.res, compute::TexelFormat::R8UI, "nbmask");
    compute::Texture3D pressure(grid.res, compute::TexelFormat::R32F, "pressure");
    solid.upload(shape.solid.data(), shape.solid.size());
    obstacle::Classifier classifier(grid);
    compute::Texture3D face_open(grid.res + 1, compute::TexelFormat::RGBA32F, "face fractions");
    classifier.binaryFractions(solid, face_open, obstacle::wholeGrid(grid.res));
    classifier.classify(solid, face_open, cls, nbmask, false, obstacle::wholeGrid(grid.res));
    force::ForceReducer reducer(grid);
    GroupReducer groups(force::ForceReducer::partialsNeeded(grid), 3);
    std::vector<force::BodyForce> out;
    for (const ForceCase& c : cases) {
      std::vector<float> p(grid.cells());
      for (int k = 0; k < grid.res.z; ++k)
        for (int j = 0; j < grid.res.y; ++j)
          for (int i = 0; i < grid.res.x; ++i) p[shape.idx(i, j, k)] = c.pressure(i, j, k);
      pressure.upload(p.data(), p.size() * sizeof(float));
      const glm::vec3 p0 = grid.toWorld(glm::vec3(grid.res) * 0.5f);
      reducer.reduce(pressure, cls, nbmask, face_open, c.box, false, c.rho_g, p0, groups, force::ForceSlots{});
      out.push_back(force::ForceReducer::decode(groups.readResults(), force::ForceSlots{}, p0, std::nullopt));
    }
    return out;
  });
}

class ForceReducerTest : public test::DeviceTest {};

TEST_F(ForceReducerTest, ClosedSurfaceKnownAnswers) {
  const Shape shape = makeShape();
  fluid::Grid grid;
  grid.res = shape.res;
  grid.cell_size_m = 0.05f;
  grid.origin_m = glm::vec3(-0.3f, 0.1f, 2.0f);
  const double h = grid.cell_size_m;
  const double area = h * h;
  const int faces = shape.exposedFaces();
  const double volume = static_cast<double>(shape.count()) * h * h * h;
  ASSERT_EQ(faces, 2 * (4 * 5 + 5 * 6 + 4 * 6) + 6 * 4 + (5 * 4 + 4 * 4 - 2));  // box + cavity + L
  const obstacle::CellBox whole{glm::ivec3(0), grid.res};
  const glm::vec3 rho_g(3.0f, -2.0f, -9810.0f);  // N/m^3, not along an axis

  const std::vector<force::BodyForce> r = runForce(
      shape, grid,
      {
          // 1. uniform pressure: no net force on a closed surface
          {[](int, int, int) { return 1000.0f; }, glm::vec3(0.0f), glm::vec3(0.0f), whole},
          // 2. hydrostatic only: Archimedes, -rho g V, whatever the reference point
          {[](int, int, int) { return 0.0f; }, rho_g, glm::vec3(0.4f, 0.2f, 2.8f), whole},
          {[](int, int, int) { return 0.0f; }, rho_g, glm::vec3(-5.0f, 7.0f, -1.0f), whole},
          // 3. dynamic pressure 10 Pa per cell in +x: F_x = -10 Pa * h^2 * sum over x-runs (L+1)
          {[](int i, int, int) { return 10.0f * static_cast<float>(i); }, glm::vec3(0.0f), glm::vec3(0.0f), whole},
          // 4. an empty box gives exactly zero, not the previous slot value
          {[](int, int, int) { return 1000.0f; }, rho_g, glm::vec3(0.0f), obstacle::CellBox{}},
      });
  ASSERT_EQ(r.size(), 5u);

  const double p_scale = 1000.0 * area * faces;  // size of the individual terms
  EXPECT_EQ(r[0].exposed_faces, faces);
  EXPECT_NEAR(r[0].force_n.x, 0.0, 1e-6 * p_scale);
  EXPECT_NEAR(r[0].force_n.y, 0.0, 1e-6 * p_scale);
  EXPECT_NEAR(r[0].force_n.z, 0.0, 1e-6 * p_scale);

  const glm::dvec3 archimedes = -glm::dvec3(rho_g) * volume;
  for (int c : {1, 2}) {
    EXPECT_EQ(r[c].exposed_faces, faces);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(r[c].force_n[a], archimedes[a], 1e-4 * std::abs(archimedes.z)) << "case " << c << " axis " << a;
    }
  }

  // Case 3 by hand: each x-run of solid cells i0..i1 sees p(i1+1) on its +x face and p(i0-1)
  // on its -x face; the cavity's runs see the cavity cells. Sum the faces exactly on the CPU.
  double fx = 0.0;
  for (int k = 0; k < grid.res.z; ++k)
    for (int j = 0; j < grid.res.y; ++j)
      for (int i = 0; i < grid.res.x; ++i) {
        if (!shape.at(i, j, k)) continue;
        if (i + 1 < grid.res.x && !shape.at(i + 1, j, k)) fx -= 10.0 * (i + 1) * area;
        if (i - 1 >= 0 && !shape.at(i - 1, j, k)) fx += 10.0 * (i - 1) * area;
      }
  EXPECT_NEAR(r[3].force_n.x, fx, 1e-5 * std::abs(fx));
  EXPECT_NEAR(r[3].force_n.y, 0.0, 1e-6 * std::abs(fx));
  EXPECT_NEAR(r[3].force_n.z, 0.0, 1e-6 * std::abs(fx));

  EXPECT_EQ(r[4].exposed_faces, 0);
  EXPECT_EQ(r[4].force_n, glm::vec3(0.0f));
}

TEST_F(ForceReducerTest, BoxLimitsWhichBoundaryCellsCount) {
  const Shape shape = makeShape();
  fluid::Grid grid;
  grid.res = shape.res;
  grid.cell_size_m = 0.1f;
  // The box around the L-shaped piece only: cells x 8..14, y 10..12, z 9..14.
  Shape only_l = shape;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 8; ++i) only_l.solid[only_l.idx(i, j, k)] = 0;
  const obstacle::CellBox l_box{glm::ivec3(8, 10, 9), glm::ivec3(7, 3, 6)};
  const glm::vec3 rho_g(0.0f, 0.0f, -10.0f);
  const auto r = runForce(shape, grid, {{[](int, int, int) { return 0.0f; }, rho_g, glm::vec3(0.0f), l_box}});
  const double volume = static_cast<double>(only_l.count()) * 1e-3;
  EXPECT_EQ(r[0].exposed_faces, only_l.exposedFaces());
  EXPECT_NEAR(r[0].force_n.z, 10.0 * volume, 1e-5);
  EXPECT_NEAR(r[0].force_n.x, 0.0, 1e-6);
}

}  // namespace
}  // namespace hf
