// SPDX-License-Identifier: GPL-3.0-or-later
// MeshEmitter's coverage (the fraction of each cell inside the posed source mesh) against a CPU
// reference that samples the generalised winding number on the same sub-columns at many heights;
// a box's exact coverage; smooth change of the covered volume as a box moves (no flicker); the
// emission in Hold and Rate mode; and validateSourcePose / makeMeshSource errors.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "emitter/mesh_emitter.h"
#include "emitter/mesh_source.h"
#include "fluid/grid.h"
#include "compute/texture3d.h"
#include "mesh_shapes.h"
#include "test_util.h"

namespace hf::emitter {
namespace {

constexpr int S = kSourceSubsamples;

fluid::Grid testGrid() {
  fluid::Grid g;
  g.res = glm::ivec3(12, 11, 13);
  g.cell_size_m = 0.05f;
  g.origin_m = glm::vec3(-0.3f, 0.2f, 1.0f);
  return g;
}

glm::mat4 pose(const glm::vec3& translation, float angle_rad, const glm::vec3& axis, const glm::vec3& scale) {
  glm::mat4 r(1.0f);
  const glm::vec3 n = glm::normalize(axis);
  const float c = std::cos(angle_rad), s = std::sin(angle_rad);
  const glm::mat3 rot(c + n.x * n.x * (1 - c), n.y * n.x * (1 - c) + n.z * s, n.z * n.x * (1 - c) - n.y * s,
                      n.x * n.y * (1 - c) - n.z * s, c + n.y * n.y * (1 - c), n.z * n.y * (1 - c) + n.x * s,
                      n.x * n.z * (1 - c) + n.y * s, n.y * n.z * (1 - c) - n.x * s, c + n.z * n.z * (1 - c));
  for (int a = 0; a < 3; ++a) r[a] = glm::vec4(rot[a] * scale[a], 0.0f);
  r[3] = glm::vec4(translation, 1.0f);
  return r;
}

MeshSource source(const obstacle::TriangleMesh& mesh, const glm::mat4& transform, const fluid::Grid& g,
                  float density = 1.0f, float temperature_k = 0.0f,
                  fluid::SourceEmission emission = fluid::SourceEmission::Hold) {
  return makeMeshSource(mesh, transform, density, temperature_k, emission, g);
}

// The coverage of every cell for each source in turn (one emitter, so the mesh upload and the
// pose change between cases are exercised too).
std::vector<std::vector<float>> coverage(const fluid::Grid& g, const std::vector<MeshSource>& sources) {
  return test::DeviceTest::onGl([&] {
    MeshEmitter emitter(g);
    std::vector<std::vector<float>> out;
    for (const MeshSource& s : sources) {
      emitter.setSource(s);
      emitter.voxelize();
      std::vector<float> c(g.cells());
      emitter.coverage().download(c.data(), c.size() * sizeof(float));
      out.push_back(std::move(c));
    }
    return out;
  });
}

// Winding number of world triangles around x (van Oosterom-Strackee), vertices already posed.
double winding(const std::vector<glm::dvec3>& v, const std::vector<glm::uvec3>& tris, const glm::dvec3& x) {
  double total = 0.0;
  for (const auto& t : tris) {
    const glm::dvec3 a = v[t.x] - x, b = v[t.y] - x, c = v[t.z] - x;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    const double num = glm::dot(a, glm::cross(b, c));
    const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
    total += 2.0 * std::atan2(num, den);
  }
  return total / (4.0 * M_PI);
}

// CPU coverage: the S x S sub-columns of the GPU, each sampled at kHeights midpoints along z
// (so a surface crossing the cell is off by at most 1 / (2 kHeights) per sub-column).
constexpr int kHeights = 16;

std::vector<double> referenceCoverage(const fluid::Grid& g, const MeshSource& s) {
  std::vector<glm::dvec3> world;
  for (const glm::vec3& p : s.mesh->vertices_m) world.push_back(glm::dvec3(glm::dmat4(s.transform) * glm::dvec4(p, 1.0)));
  std::vector<double> out(g.cells(), 0.0);
  for (int k = 0; k < g.res.z; ++k)
    for (int j = 0; j < g.res.y; ++j)
      for (int i = 0; i < g.res.x; ++i) {
        int in = 0;
        for (int b = 0; b < S; ++b)
          for (int a = 0; a < S; ++a)
            for (int z = 0; z < kHeights; ++z) {
              const glm::dvec3 u(i + (a + 0.5) / S, j + (b + 0.5) / S, k + (z + 0.5) / kHeights);
              const glm::dvec3 x = glm::dvec3(g.origin_m) + u * double(g.cell_size_m);
              in += std::abs(winding(world, s.mesh->triangles, x)) > 0.5;
            }
        out[i + g.res.x * (j + static_cast<std::size_t>(g.res.y) * k)] = double(in) / (S * S * kHeights);
      }
  return out;
}

void expectNearReference(const fluid::Grid& g, const MeshSource& s, const std::vector<float>& got,
                         const std::string& what) {
  const std::vector<double> want = referenceCoverage(g, s);
  double worst = 0.0, volume_got = 0.0, volume_want = 0.0;
  int partial = 0;
  std::ostringstream where;
  for (std::size_t n = 0; n < want.size(); ++n) {
    const double err = std::abs(got[n] - want[n]);
    if (err > worst) {
      worst = err;
      where.str("");
      where << "cell " << n << ": GPU " << got[n] << ", CPU " << want[n];
    }
    volume_got += got[n];
    volume_want += want[n];
    partial += want[n] > 0.0 && want[n] < 1.0;
  }
  // Per sub-column the z sampling errs by at most 1/(2 kHeights) per surface crossing in the cell.
  EXPECT_LE(worst, 1.0 / kHeights + 1e-4) << what << ": worst at " << where.str();
  EXPECT_NEAR(volume_got, volume_want, 0.01 * volume_want + 0.5) << what;
  EXPECT_GT(volume_want, 20.0) << what;
  EXPECT_GT(partial, 20) << what << ": the case must have partly covered cells";
}

class MeshEmitterTest : public test::DeviceTest {};

TEST_F(MeshEmitterTest, CoverageMatchesCpuReferenceForPosedShapes) {
  const fluid::Grid g = testGrid();
  const glm::vec3 mid = g.origin_m + 0.5f * g.sizeM();
  std::vector<MeshSource> cases;
  std::vector<std::string> names;
  cases.push_back(source(test::boxMesh(glm::vec3(-0.2f), glm::vec3(0.2f)),
                         pose(mid + glm::vec3(0.013f, -0.02f, 0.031f), 0.61f, glm::vec3(1, 2, 3),
                              glm::vec3(0.9f, 0.6f, 0.7f)), g));
  names.push_back("rotated, scaled box");
  cases.push_back(source(test::tetraMesh({glm::vec3(-0.2f, -0.17f, -0.13f), glm::vec3(0.22f, -0.13f, -0.2f),
                                          glm::vec3(0.01f, 0.2f, -0.15f), glm::vec3(0.03f, 0.01f, 0.24f)}),
                         pose(mid, 1.2f, glm::vec3(-1, 0.3f, 0.5f), glm::vec3(1.0f)), g));
  names.push_back("tetrahedron");
  cases.push_back(source(test::icosphere(1, 0.2f, glm::vec3(0.0f)),
                         pose(mid + glm::vec3(0.011f, 0.007f, -0.013f), 0.4f, glm::vec3(0, 1, 1),
                              glm::vec3(1.3f, 0.8f, 1.0f)), g));
  names.push_back("icosphere (80 triangles), stretched and turned");
  // Mirrored: inside out as a whole; the coverage is the same.
  cases.push_back(source(test::icosphere(1, 0.2f, glm::vec3(0.0f)),
                         pose(mid, 0.3f, glm::vec3(1, 1, 0), glm::vec3(-1.0f, 1.0f, 1.0f)), g));
  names.push_back("mirrored icosphere");
  // Reaching out of the domain below and at -x: only the part inside is covered.
  cases.push_back(source(test::boxMesh(glm::vec3(-0.2f), glm::vec3(0.2f)),
                         pose(g.origin_m + glm::vec3(0.05f, 0.27f, 0.08f), 0.3f, glm::vec3(0, 0, 1), glm::vec3(1.0f)),
                         g));
  names.push_back("box through the floor and a wall");
  const auto got = coverage(g, cases);
  for (std::size_t c = 0; c < cases.size(); ++c) expectNearReference(g, cases[c], got[c], names[c]);
}

// An axis-aligned box: per axis the coverage is the fraction of the S sub-column lines inside
// (x, y) or the overlap length (z, exact); the cell's coverage is their product.
TEST_F(MeshEmitterTest, AxisAlignedBoxHasItsExactCoverage) {
  fluid::Grid g;
  g.res = glm::ivec3(10, 9, 8);
  g.cell_size_m = 0.1f;
  const glm::vec3 lo(0.23f, 0.31f, 0.17f), hi(0.71f, 0.66f, 0.58f);
  const auto got = coverage(g, {source(test::boxMesh(lo, hi), glm::mat4(1.0f), g)})[0];
  auto lines = [&](int i, float a, float b) {
    int in = 0;
    for (int s = 0; s < S; ++s) {
      const float x = (i + (s + 0.5f) / S) * g.cell_size_m;
      in += x > a && x < b;
    }
    return float(in) / S;
  };
  auto overlap = [&](int k, float a, float b) {
    return std::max(0.0f, std::min(b, (k + 1) * g.cell_size_m) - std::max(a, k * g.cell_size_m)) / g.cell_size_m;
  };
  for (int k = 0; k < g.res.z; ++k)
    for (int j = 0; j < g.res.y; ++j)
      for (int i = 0; i < g.res.x; ++i) {
        const float want = lines(i, lo.x, hi.x) * lines(j, lo.y, hi.y) * overlap(k, lo.z, hi.z);
        ASSERT_NEAR(got[i + g.res.x * (j + g.res.y * k)], want, 1e-4f) << i << " " << j << " " << k;
      }
}

// A box sliding along x in sixteenths of a cell: the covered volume moves in steps of at most one
// sub-column row (its yz face x h / S), never a whole cell layer, and is back to the exact
// volume whenever its faces sit between sub-column lines.
TEST_F(MeshEmitterTest, CoveredVolumeChangesSmoothlyAsTheSourceMoves) {
  fluid::Grid g;
  g.res = glm::ivec3(16, 10, 10);
  g.cell_size_m = 0.1f;
  const glm::vec3 size(0.3f, 0.4f, 0.35f);
  const obstacle::TriangleMesh box = test::boxMesh(-0.5f * size, 0.5f * size);
  std::vector<MeshSource> cases;
  for (int s = 0; s <= 32; ++s) {
    cases.push_back(source(box, pose(glm::vec3(0.5f + s * g.cell_size_m / 16, 0.5f, 0.5f), 0.0f, glm::vec3(0, 0, 1),
                                     glm::vec3(1.0f)), g));
  }
  const auto got = coverage(g, cases);
  const double cell_volume = std::pow(g.cell_size_m, 3.0);
  const double exact = double(size.x) * size.y * size.z;
  const double row = double(size.y) * size.z * g.cell_size_m / S;  // one sub-column row through the box
  for (std::size_t c = 0; c < got.size(); ++c) {
    double v = 0.0;
    for (float x : got[c]) v += x * cell_volume;
    EXPECT_LE(std::abs(v - exact), row + 1e-6) << "offset " << c << "/16 cell";
  }
}

TEST_F(MeshEmitterTest, HoldRaisesAndRateAddsByCoverage) {
  fluid::Grid g;
  g.res = glm::ivec3(10, 9, 8);
  g.cell_size_m = 0.1f;
  const obstacle::TriangleMesh box = test::boxMesh(glm::vec3(0.23f, 0.31f, 0.17f), glm::vec3(0.71f, 0.66f, 0.58f));
  const float dt = 0.25f;
  struct Result {
    std::vector<float> cover, hold_d, hold_t, rate_d, rate_t;
  };
  const Result r = test::DeviceTest::onGl([&] {
    Result out;
    compute::Texture3D density(g.res, compute::TexelFormat::R32F, "density");
    compute::Texture3D temperature(g.res, compute::TexelFormat::R32F, "temperature");
    compute::Texture3D nbmask(g.res, compute::TexelFormat::R8UI, "nbmask");
    nbmask.clear();
    std::vector<float> start(g.cells(), 0.3f);
    auto run = [&](const MeshSource& s, std::vector<float>& d, std::vector<float>& t) {
      density.upload(start.data(), start.size() * sizeof(float));
      temperature.upload(start.data(), start.size() * sizeof(float));
      MeshEmitter e(g);
      e.setSource(s);
      e.voxelize();
      e.emit(density, temperature, nbmask, dt);
      d.resize(g.cells());
      t.resize(g.cells());
      density.download(d.data(), d.size() * sizeof(float));
      temperature.download(t.data(), t.size() * sizeof(float));
      out.cover.resize(g.cells());
      e.coverage().download(out.cover.data(), out.cover.size() * sizeof(float));
    };
    run(source(box, glm::mat4(1.0f), g, 0.8f, 5.0f, fluid::SourceEmission::Hold), out.hold_d, out.hold_t);
    run(source(box, glm::mat4(1.0f), g, 0.8f, 5.0f, fluid::SourceEmission::Rate), out.rate_d, out.rate_t);
    return out;
  });
  int full = 0, partial = 0;
  for (std::size_t n = 0; n < g.cells(); ++n) {
    const float c = r.cover[n];
    full += c == 1.0f;
    partial += c > 0.0f && c < 1.0f;
    EXPECT_FLOAT_EQ(r.hold_d[n], std::max(0.3f, 0.8f * c)) << n;
    EXPECT_FLOAT_EQ(r.hold_t[n], std::max(0.3f, 5.0f * c)) << n;
    EXPECT_NEAR(r.rate_d[n], 0.3f + 0.8f * c * dt, 1e-6f) << n;
    EXPECT_NEAR(r.rate_t[n], 0.3f + 5.0f * c * dt, 1e-5f) << n;
  }
  EXPECT_GT(full, 10);
  EXPECT_GT(partial, 10);
}

TEST(MeshSourceChecks, RefusesBadSourcesSayingWhatToChange) {
  fluid::Grid g;
  g.res = glm::ivec3(10, 10, 10);
  g.cell_size_m = 0.1f;
  const obstacle::TriangleMesh box = test::boxMesh(glm::vec3(-0.1f), glm::vec3(0.1f));
  auto message = [&](const obstacle::TriangleMesh& m, const glm::mat4& t, float density = 1.0f) {
    try {
      makeMeshSource(m, t, density, 0.0f, fluid::SourceEmission::Hold, g);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const glm::mat4 inside = pose(glm::vec3(0.5f), 0.0f, glm::vec3(0, 0, 1), glm::vec3(1.0f));
  EXPECT_EQ(message(box, inside), "accepted");
  EXPECT_EQ(message(box, pose(glm::vec3(0.95f, 0.5f, 0.5f), 0.0f, glm::vec3(0, 0, 1), glm::vec3(1.0f))), "accepted")
      << "a source reaching out of the domain is fine";
  EXPECT_NE(message(box, pose(glm::vec3(1.5f, 0.5f, 0.5f), 0.0f, glm::vec3(0, 0, 1), glm::vec3(1.0f)))
                .find("move the smoke source into the domain"), std::string::npos);
  EXPECT_NE(message(box, pose(glm::vec3(0.5f), 0.0f, glm::vec3(0, 0, 1), glm::vec3(30.0f))).find("cut or scale down"),
            std::string::npos);
  obstacle::TriangleMesh open = box;
  open.triangles.pop_back();
  EXPECT_EQ(message(open, inside).rfind("smoke source mesh: ", 0), 0u) << message(open, inside);
  EXPECT_NE(message(box, inside, -1.0f).find("smoke source density"), std::string::npos);
  glm::mat4 flat = inside;
  flat[2] = glm::vec4(0.0f);
  EXPECT_NE(message(box, flat).find("singular"), std::string::npos);
}

}  // namespace
}  // namespace hf::emitter
