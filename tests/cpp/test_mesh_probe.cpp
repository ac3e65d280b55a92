// SPDX-License-Identifier: GPL-3.0-or-later
// MeshProbe::voxelize against a CPU point-in-mesh reference (generalised winding number) on
// every cell of a small grid, for a box, a tetrahedron and an icosphere under translation,
// rotation and non-uniform scale; the exact tie rule on columns through edges and vertices;
// zero-area triangles, split vertices, inside-out and overlapping shells; the rigid velocity;
// and validateMesh's errors for open, misoriented and malformed meshes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "fluid/grid.h"
#include "compute/texture3d.h"
#include "mesh_shapes.h"
#include "obstacle/mesh_probe.h"
#include "test_util.h"

namespace hf::obstacle {
namespace {

struct Voxels {
  std::vector<std::uint8_t> solid;
  std::vector<glm::vec4> velocity;
};

fluid::Grid testGrid() {
  fluid::Grid g;
  g.res = glm::ivec3(20, 18, 22);
  g.cell_size_m = 0.05f;
  g.origin_m = glm::vec3(-0.4f, 0.3f, 1.0f);
  return g;
}

// Voxelizes each (mesh, pose) in turn with one MeshProbe and one pair of textures.
std::vector<Voxels> voxelize(const fluid::Grid& g, const std::vector<std::pair<TriangleMesh, RigidPose>>& cases) {
  return test::DeviceTest::onGl([&] {
    compute::Texture3D solid(g.res, compute::TexelFormat::R8UI, "solid");
    compute::Texture3D velocity(g.res, compute::TexelFormat::RGBA32F, "solid velocity");
    MeshProbe probe(g);
    std::vector<Voxels> out;
    for (const auto& [mesh, pose] : cases) {
      probe.setMesh(std::make_shared<const TriangleMesh>(mesh));
      probe.setPose(pose);
      probe.voxelize(solid, velocity, obstacle::wholeGrid(g.res));
      Voxels v;
      v.solid.resize(g.cells());
      v.velocity.resize(g.cells());
      solid.download(v.solid.data(), v.solid.size());
      velocity.download(v.velocity.data(), v.velocity.size() * sizeof(glm::vec4));
      out.push_back(std::move(v));
    }
    return out;
  });
}

glm::mat4 pose(const glm::vec3& translation, float angle_rad, const glm::vec3& axis, const glm::vec3& scale) {
  const glm::vec3 n = glm::normalize(axis);
  const float c = std::cos(angle_rad), s = std::sin(angle_rad);
  glm::mat3 r(c + n.x * n.x * (1 - c), n.y * n.x * (1 - c) + n.z * s, n.z * n.x * (1 - c) - n.y * s,
              n.x * n.y * (1 - c) - n.z * s, c + n.y * n.y * (1 - c), n.z * n.y * (1 - c) + n.x * s,
              n.x * n.z * (1 - c) + n.y * s, n.y * n.z * (1 - c) - n.x * s, c + n.z * n.z * (1 - c));
  glm::mat4 m(1.0f);
  for (int a = 0; a < 3; ++a) m[a] = glm::vec4(r[a] * scale[a], 0.0f);
  m[3] = glm::vec4(translation, 1.0f);
  return m;
}

// Compares every cell with the CPU reference. Cells whose centre is within float noise of the
// surface (winding number near 1/2) may go either way; there must be few of them.
void expectMatchesReference(const fluid::Grid& g, const TriangleMesh& mesh, const RigidPose& p, const Voxels& v,
                            const std::string& what) {
  int solid = 0, mismatches = 0, ambiguous = 0;
  std::ostringstream first;
  for (int k = 0; k < g.res.z; ++k)
    for (int j = 0; j < g.res.y; ++j)
      for (int i = 0; i < g.res.x; ++i) {
        const std::size_t n = i + g.res.x * (j + static_cast<std::size_t>(g.res.y) * k);
        const glm::dvec3 x(g.toWorld(glm::vec3(i, j, k) + 0.5f));
        const double w = test::windingNumber(mesh, glm::dmat4(p.transform), x);
        const bool want = std::abs(w) > 0.5;
        solid += want;
        if (std::abs(std::abs(w) - 0.5) < 0.02) {
          ++ambiguous;
          continue;
        }
        if ((v.solid[n] != 0) != want) {
          if (mismatches++ == 0) first << "cell (" << i << ", " << j << ", " << k << ") winding " << w;
        }
      }
  EXPECT_EQ(mismatches, 0) << what << ": first " << first.str();
  EXPECT_GT(solid, 20) << what;
  EXPECT_LT(ambiguous, solid / 20 + 2) << what;
}

class MeshProbeTest : public test::DeviceTest {};

TEST_F(MeshProbeTest, MatchesCpuPointInMeshForPosedShapes) {
  const fluid::Grid g = testGrid();
  const glm::vec3 mid = g.origin_m + 0.5f * g.sizeM();
  std::vector<std::pair<TriangleMesh, RigidPose>> cases;
  std::vector<std::string> names;
  auto add = [&](const std::string& name, TriangleMesh m, const glm::mat4& t) {
    RigidPose p;
    p.transform = t;
    cases.emplace_back(std::move(m), p);
    names.push_back(name);
  };
  add("axis-aligned box", test::boxMesh(glm::vec3(-0.21f, -0.17f, -0.26f), glm::vec3(0.19f, 0.23f, 0.13f)),
      pose(mid, 0.0f, glm::vec3(0, 0, 1), glm::vec3(1.0f)));
  add("rotated, scaled box", test::boxMesh(glm::vec3(-0.2f), glm::vec3(0.2f)),
      pose(mid + glm::vec3(0.013f, -0.02f, 0.031f), 0.61f, glm::vec3(1, 2, 3), glm::vec3(1.1f, 0.7f, 0.9f)));
  add("tetrahedron",
      test::tetraMesh({glm::vec3(-0.3f, -0.25f, -0.2f), glm::vec3(0.33f, -0.2f, -0.31f),
                       glm::vec3(0.02f, 0.31f, -0.22f), glm::vec3(0.05f, 0.01f, 0.36f)}),
      pose(mid, 1.2f, glm::vec3(-1, 0.3f, 0.5f), glm::vec3(1.0f)));
  add("icosphere (320 triangles), stretched and turned", test::icosphere(2, 0.3f, glm::vec3(0.0f)),
      pose(mid + glm::vec3(0.011f, 0.007f, -0.013f), 0.4f, glm::vec3(0, 1, 1), glm::vec3(1.3f, 0.8f, 1.0f)));
  // A mirroring transform turns the mesh inside out; the nonzero rule does not care.
  add("mirrored tetrahedron",
      test::tetraMesh({glm::vec3(-0.3f, -0.25f, -0.2f), glm::vec3(0.33f, -0.2f, -0.31f),
                       glm::vec3(0.02f, 0.31f, -0.22f), glm::vec3(0.05f, 0.01f, 0.36f)}),
      pose(mid, 0.3f, glm::vec3(1, 1, 0), glm::vec3(-1.0f, 1.0f, 1.0f)));
  const std::vector<Voxels> got = voxelize(g, cases);
  for (std::size_t c = 0; c < cases.size(); ++c) expectMatchesReference(g, cases[c].first, cases[c].second, got[c], names[c]);
}

// Vertices exactly on column centres: the columns through the box's edges, corners and the
// faces' diagonals must each be counted once. With the (e, e^2) tie rule the box [2.5, 7.5]^2
// in x, y covers columns 2..6 exactly; z spans 2.3..6.7 -> cells 2..6.
TEST_F(MeshProbeTest, ColumnsThroughEdgesAndVerticesCountOnce) {
  fluid::Grid g;
  g.res = glm::ivec3(10, 10, 10);
  g.cell_size_m = 0.1f;
  RigidPose p;
  std::vector<std::pair<TriangleMesh, RigidPose>> cases;
  cases.emplace_back(test::boxMesh(glm::vec3(0.25f, 0.25f, 0.23f), glm::vec3(0.75f, 0.75f, 0.67f)), p);
  // The same box with 24 unshared vertices, a zero-area sliver and a collapsed triangle added.
  TriangleMesh split;
  const TriangleMesh box = cases[0].first;
  for (const auto& t : box.triangles) {
    const auto base = static_cast<unsigned>(split.vertices_m.size());
    for (int c = 0; c < 3; ++c) split.vertices_m.push_back(box.vertices_m[t[c]]);
    split.triangles.emplace_back(base, base + 1, base + 2);
  }
  split.triangles.emplace_back(0, 0, 1);  // collapsed
  split.triangles.emplace_back(0, 1, 0);  // collapsed, other way round
  cases.emplace_back(split, p);
  for (const auto& c : cases) ASSERT_NO_THROW(validateMesh(c.first));
  const std::vector<Voxels> got = voxelize(g, cases);
  for (std::size_t c = 0; c < got.size(); ++c) {
    int wrong = 0;
    for (int k = 0; k < 10; ++k)
      for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 10; ++i) {
          const bool want = i >= 2 && i <= 6 && j >= 2 && j <= 6 && k >= 2 && k <= 6;
          wrong += (got[c].solid[i + 10 * (j + 10 * k)] != 0) != want;
        }
    EXPECT_EQ(wrong, 0) << "case " << c;
  }
}

TEST_F(MeshProbeTest, OverlappingShellsGiveTheirUnion) {
  const fluid::Grid g = testGrid();
  const glm::vec3 mid = g.origin_m + 0.5f * g.sizeM();
  TriangleMesh two = test::boxMesh(glm::vec3(-0.3f, -0.1f, -0.1f), glm::vec3(0.1f, 0.1f, 0.1f));
  const TriangleMesh b = test::boxMesh(glm::vec3(-0.1f, -0.3f, -0.2f), glm::vec3(0.2f, 0.2f, 0.05f));
  for (const auto& t : b.triangles) two.triangles.push_back(t + glm::uvec3(8));
  two.vertices_m.insert(two.vertices_m.end(), b.vertices_m.begin(), b.vertices_m.end());
  ASSERT_NO_THROW(validateMesh(two));
  RigidPose p;
  p.transform = pose(mid + glm::vec3(0.012f, 0.017f, 0.021f), 0.2f, glm::vec3(0, 0, 1), glm::vec3(1.0f));
  const Voxels v = voxelize(g, {{two, p}})[0];
  // Winding number 2 in the overlap: solid too (|w| > 1/2 in the reference).
  expectMatchesReference(g, two, p, v, "two overlapping boxes");
}

TEST_F(MeshProbeTest, SolidCellsMoveRigidly) {
  const fluid::Grid g = testGrid();
  const glm::vec3 centre = g.origin_m + 0.5f * g.sizeM() + glm::vec3(0.02f, -0.01f, 0.0f);
  RigidPose p;
  p.transform = pose(centre, 0.5f, glm::vec3(1, 0, 1), glm::vec3(1.0f));
  p.velocity_m_s = glm::vec3(0.4f, -0.3f, 0.2f);
  p.angular_velocity_rad_s = glm::vec3(2.0f, -1.0f, 3.0f);
  const Voxels v = voxelize(g, {{test::icosphere(1, 0.3f, glm::vec3(0.0f)), p}})[0];
  int solid = 0;
  for (int k = 0; k < g.res.z; ++k)
    for (int j = 0; j < g.res.y; ++j)
      for (int i = 0; i < g.res.x; ++i) {
        const std::size_t n = i + g.res.x * (j + static_cast<std::size_t>(g.res.y) * k);
        const glm::vec3 x = g.toWorld(glm::vec3(i, j, k) + 0.5f);
        // At every cell centre, solid or not (cut faces beside fluid cells read it).
        const glm::vec3 want = p.velocity_m_s + glm::cross(p.angular_velocity_rad_s, x - centre);
        solid += v.solid[n] != 0;
        for (int a = 0; a < 3; ++a) ASSERT_NEAR(v.velocity[n][a], want[a], 1e-5f) << i << " " << j << " " << k;
      }
  EXPECT_GT(solid, 100);
}

TEST(MeshValidation, RejectsOpenMisorientedAndMalformedMeshes) {
  auto message = [](const TriangleMesh& m) {
    try {
      validateMesh(m);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const TriangleMesh box = test::boxMesh(glm::vec3(0.0f), glm::vec3(1.0f));
  EXPECT_EQ(message(box), "(no error)");
  TriangleMesh open = box;
  open.triangles.pop_back();
  EXPECT_TRUE(test::contains(message(open), "not closed")) << message(open);
  TriangleMesh flipped = box;
  std::swap(flipped.triangles[3].y, flipped.triangles[3].z);
  EXPECT_TRUE(test::contains(message(flipped), "consistently oriented")) << message(flipped);
  TriangleMesh bad_index = box;
  bad_index.triangles[5].z = 8;
  EXPECT_TRUE(test::contains(message(bad_index), "vertex index 8")) << message(bad_index);
  TriangleMesh nan = box;
  nan.vertices_m[2].y = NAN;
  EXPECT_TRUE(test::contains(message(nan), "not finite")) << message(nan);
  EXPECT_TRUE(test::contains(message(TriangleMesh{}), "empty"));

  EXPECT_THROW(validateTransform(glm::mat4(0.0f)), InvalidArgument);  // not affine
  glm::mat4 flat(1.0f);
  flat[2][2] = 0.0f;
  EXPECT_THROW(validateTransform(flat), InvalidArgument);  // singular
  glm::mat4 inf(1.0f);
  inf[3][0] = INFINITY;
  EXPECT_THROW(validateTransform(inf), InvalidArgument);
  EXPECT_NO_THROW(validateTransform(pose(glm::vec3(1, 2, 3), 0.3f, glm::vec3(1, 0, 0), glm::vec3(2, 0.5f, -1))));
}

// worldBox holds the posed mesh: every transformed vertex is inside it, and for a box mesh
// (whose corners are its vertices) it is tight.
TEST(MeshValidation, WorldBoxHoldsThePosedMesh) {
  const TriangleMesh sphere = test::icosphere(2, 0.5f, glm::vec3(0.1f, 0.0f, -0.2f));
  const glm::mat4 m = pose(glm::vec3(1, -2, 3), 0.8f, glm::vec3(1, 1, 0), glm::vec3(2.0f, 1.0f, 0.5f));
  const WorldBox b = worldBox(meshExtent(sphere), m);
  for (const auto& v : sphere.vertices_m) {
    const glm::vec3 w(m * glm::vec4(v, 1.0f));
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(w[a], b.lo[a] - 1e-5f);
      EXPECT_LE(w[a], b.hi[a] + 1e-5f);
    }
  }
  const TriangleMesh box = test::boxMesh(glm::vec3(-1.0f), glm::vec3(1.0f));
  const WorldBox bb = worldBox(meshExtent(box), glm::mat4(1.0f));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(bb.lo[a], -1.0f, 1e-5f);
    EXPECT_NEAR(bb.hi[a], 1.0f, 1e-5f);
  }
}

// columnVisitBound is an upper bound on the columns the crossings stage visits: each triangle's
// columns with centres inside its posed xy box, counted here exactly.
TEST(MeshValidation, ColumnVisitBoundHoldsTheCrossingsWork) {
  const fluid::Grid g = testGrid();
  for (const TriangleMesh& mesh : {test::boxMesh(glm::vec3(-0.3f), glm::vec3(0.2f, 0.3f, 0.25f)),
                                   test::icosphere(2, 0.3f, glm::vec3(0.0f))}) {
    const glm::mat4 m = pose(glm::vec3(0.1f, 0.7f, 1.5f), 0.9f, glm::vec3(1, -2, 1), glm::vec3(1.3f, 0.6f, 1.0f));
    double visits = 0.0;
    for (const auto& t : mesh.triangles) {
      glm::vec2 lo(1e30f), hi(-1e30f);
      for (int c = 0; c < 3; ++c) {
        const glm::vec3 p = g.toGrid(glm::vec3(m * glm::vec4(mesh.vertices_m[t[c]], 1.0f)));
        lo = glm::min(lo, glm::vec2(p));
        hi = glm::max(hi, glm::vec2(p));
      }
      const glm::vec2 n = glm::max(glm::floor(hi - 0.5f) - glm::ceil(lo - 0.5f) + 1.0f, glm::vec2(0.0f));
      visits += double(n.x) * n.y;
    }
    const double bound = columnVisitBound(meshExtent(mesh), m, g.cell_size_m);
    EXPECT_GE(bound, visits);
    EXPECT_LT(bound, 20.0 * visits + 1000.0);  // and not uselessly loose
  }
}

}  // namespace
}  // namespace hf::obstacle
