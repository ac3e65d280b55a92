// SPDX-License-Identifier: GPL-3.0-or-later
// Cut cells of mesh probes (MeshProbe::writeFaceFractions): every face's open fraction is the
// fluid share of the fine cells in its control volume (the cell-sized box centred on the face).
// Known answers: an axis-aligned box whose sides lie between fine cell centres gives exactly the
// analytic overlap of each control volume with the box; posed meshes (a turned, scaled box and a
// stretched icosphere) match a CPU reference that decides every fine cell centre with the
// generalised winding number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "fluid/grid.h"
#include "compute/texture3d.h"
#include "mesh_shapes.h"
#include "obstacle/mesh_probe.h"
#include "test_util.h"

namespace hf::obstacle {
namespace {

struct Fractions {
  std::vector<glm::vec4> open;  // (res + 1)^3 texels, x/y/z faces of one index per texel
  CellBox box;                  // the probe's cell box (the fine grid's extent)
};

Fractions faceFractions(const fluid::Grid& g, const TriangleMesh& mesh, const RigidPose& pose) {
  return test::DeviceTest::onGl([&] {
    compute::Texture3D solid(g.res, compute::TexelFormat::R8UI, "solid");
    compute::Texture3D velocity(g.res, compute::TexelFormat::RGBA32F, "solid velocity");
    compute::Texture3D open(g.res + 1, compute::TexelFormat::RGBA32F, "face open fractions");
    MeshProbe probe(g);
    probe.setMesh(std::make_shared<const TriangleMesh>(mesh));
    probe.setPose(pose);
    probe.setCutCells(true);
    probe.voxelize(solid, velocity, obstacle::wholeGrid(g.res));
    Fractions f;
    EXPECT_TRUE(probe.writeFaceFractions(open, obstacle::wholeGrid(g.res)));
    f.box = probe.bounds();
    const glm::ivec3 t = g.res + 1;
    f.open.resize(static_cast<std::size_t>(t.x) * t.y * t.z);
    open.download(f.open.data(), f.open.size() * sizeof(glm::vec4));
    return f;
  });
}

// common.glsl's cutOffOpen with obstacle::kMinOpenFraction.
float cutOff(float w) {
  const float m = kMinOpenFraction;
  return w >= 2.0f * m ? std::min(w, 1.0f) : std::max(2.0f * (w - m), 0.0f);
}

// The control volume of face `idx` on `axis`, grid units: [lo, lo + 1) per axis.
glm::dvec3 controlLow(const glm::ivec3& idx, int axis) {
  glm::dvec3 lo(idx);
  lo[axis] -= 0.5;
  return lo;
}

// Visits the three faces of every texel of `f.open`: fn(idx, axis, got, in_grid), where in_grid
// says the face is one of the grid's (an x face has i <= res.x, j < res.y, k < res.z, ...).
template <class Fn>
void forEachFace(const glm::ivec3& res, const Fractions& f, Fn fn) {
  for (int k = 0; k <= res.z; ++k)
    for (int j = 0; j <= res.y; ++j)
      for (int i = 0; i <= res.x; ++i) {
        const glm::ivec3 idx(i, j, k);
        const glm::vec4 got = f.open[i + (res.x + 1) * (j + (res.y + 1) * static_cast<std::size_t>(k))];
        for (int a = 0; a < 3; ++a) fn(idx, a, got[a], glm::all(glm::lessThan(idx, res + glm::ivec3(a == 0, a == 1, a == 2))));
      }
}

// Counts faces off their expected value and describes the first.
struct Misses {
  int count = 0;
  std::ostringstream first;
  template <class Want>
  void add(const glm::ivec3& idx, int axis, float got, const Want& want) {
    if (count++ == 0) first << "face " << axis << " (" << idx.x << ", " << idx.y << ", " << idx.z << "): " << got << " want " << want;
  }
};

class MeshFractionsTest : public test::DeviceTest {};

TEST_F(MeshFractionsTest, AxisAlignedBoxGivesTheExactControlVolumeOverlap) {
  fluid::Grid g;
  g.res = glm::ivec3(12, 13, 14);
  g.cell_size_m = 0.1f;
  // Sides at multiples of a quarter cell: between the fine cell centres (eighths), so the fine
  // voxelization is exact.
  const glm::dvec3 lo(3.25, 2.75, 4.0), hi(8.5, 7.0, 9.25);
  RigidPose p;  // identity: the mesh is given in world metres
  const TriangleMesh box = test::boxMesh(glm::vec3(lo * 0.1), glm::vec3(hi * 0.1));
  ASSERT_EQ(MeshProbe::fineCellsFor(1000), kFineCells);
  const Fractions f = faceFractions(g, box, p);
  int partial = 0;
  Misses wrong;
  forEachFace(g.res, f, [&](const glm::ivec3& idx, int a, float got, bool in_grid) {
    float want = 1.0f;
    if (in_grid) {
      const glm::dvec3 c = controlLow(idx, a);
      double overlap = 1.0;
      for (int b = 0; b < 3; ++b) overlap *= std::max(0.0, std::min(c[b] + 1.0, hi[b]) - std::max(c[b], lo[b]));
      want = cutOff(static_cast<float>(1.0 - overlap));
      partial += want > 0.0f && want < 1.0f;
    }
    if (std::abs(got - want) > 1e-5f) wrong.add(idx, a, got, want);
  });
  EXPECT_EQ(wrong.count, 0) << wrong.first.str();
  EXPECT_GT(partial, 200);
}

TEST_F(MeshFractionsTest, PosedMeshesMatchACpuWindingNumberReference) {
  fluid::Grid g;
  g.res = glm::ivec3(20, 18, 22);
  g.cell_size_m = 0.05f;
  g.origin_m = glm::vec3(-0.4f, 0.3f, 1.0f);
  const glm::vec3 mid = g.origin_m + 0.5f * g.sizeM();
  struct Case {
    const char* name;
    TriangleMesh mesh;
    glm::vec3 axis, scale, offset;
    float angle;
  };
  const std::vector<Case> cases = {
      {"turned, scaled box", test::boxMesh(glm::vec3(-0.17f), glm::vec3(0.17f)), glm::vec3(1, 2, 3),
       glm::vec3(1.1f, 0.7f, 0.9f), glm::vec3(0.013f, -0.02f, 0.031f), 0.61f},
      {"stretched icosphere (80 triangles)", test::icosphere(1, 0.25f, glm::vec3(0.0f)), glm::vec3(0, 1, 1),
       glm::vec3(1.3f, 0.8f, 1.0f), glm::vec3(0.011f, 0.007f, -0.013f), 0.4f},
  };
  for (const Case& c : cases) {
    const glm::vec3 n = glm::normalize(c.axis);
    const float co = std::cos(c.angle), si = std::sin(c.angle);
    const glm::mat3 r(co + n.x * n.x * (1 - co), n.y * n.x * (1 - co) + n.z * si, n.z * n.x * (1 - co) - n.y * si,
                      n.x * n.y * (1 - co) - n.z * si, co + n.y * n.y * (1 - co), n.z * n.y * (1 - co) + n.x * si,
                      n.x * n.z * (1 - co) + n.y * si, n.y * n.z * (1 - co) - n.x * si, co + n.z * n.z * (1 - co));
    RigidPose p;
    for (int a = 0; a < 3; ++a) p.transform[a] = glm::vec4(r[a] * c.scale[a], 0.0f);
    p.transform[3] = glm::vec4(mid + c.offset, 1.0f);
    const Fractions f = faceFractions(g, c.mesh, p);
    const std::size_t box_cells = static_cast<std::size_t>(f.box.extent.x) * f.box.extent.y * f.box.extent.z;
    const int s = MeshProbe::fineCellsFor(box_cells);
    // Every fine cell of the box: 1 solid, 0 fluid, -1 too near the surface to call.
    const glm::ivec3 fr = f.box.extent * s;
    std::vector<signed char> fine(static_cast<std::size_t>(fr.x) * fr.y * fr.z);
    const glm::dmat4 t(p.transform);
    for (int k = 0; k < fr.z; ++k)
      for (int j = 0; j < fr.y; ++j)
        for (int i = 0; i < fr.x; ++i) {
          const glm::dvec3 at = glm::dvec3(f.box.origin) + (glm::dvec3(i, j, k) + 0.5) / double(s);
          const glm::dvec3 x = glm::dvec3(g.origin_m) + at * double(g.cell_size_m);
          const double w = std::abs(test::windingNumber(c.mesh, t, x));
          fine[i + fr.x * (j + static_cast<std::size_t>(fr.y) * k)] = std::abs(w - 0.5) < 0.02 ? -1 : (w > 0.5);
        }
    int partial = 0;
    Misses wrong;
    forEachFace(g.res, f, [&](const glm::ivec3& idx, int a, float got, bool in_grid) {
      if (!in_grid) return;
      glm::ivec3 lo = (idx - f.box.origin) * s;
      lo[a] -= s / 2;
      int solid = 0, unsure = 0;
      for (int z = lo.z; z < lo.z + s; ++z)
        for (int y = lo.y; y < lo.y + s; ++y)
          for (int x = lo.x; x < lo.x + s; ++x) {
            if (x < 0 || y < 0 || z < 0 || x >= fr.x || y >= fr.y || z >= fr.z) continue;
            const signed char v = fine[x + fr.x * (y + static_cast<std::size_t>(fr.y) * z)];
            solid += v == 1;
            unsure += v == -1;
          }
      const float cube = float(s * s * s);
      const float most = cutOff(1.0f - solid / cube), least = cutOff(1.0f - (solid + unsure) / cube);
      partial += most > 0.0f && most < 1.0f;
      if (got < least - 1e-5f || got > most + 1e-5f) {
        std::ostringstream range;
        range << least << " .. " << most;
        wrong.add(idx, a, got, range.str());
      }
    });
    EXPECT_EQ(wrong.count, 0) << c.name << ": first " << wrong.first.str();
    EXPECT_GT(partial, 100) << c.name;
  }
}

}  // namespace
}  // namespace hf::obstacle
