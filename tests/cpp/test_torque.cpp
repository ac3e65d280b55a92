// SPDX-License-Identifier: GPL-3.0-or-later
// ForceReducer's torque and centroid: a voxel box in a hydrostatic field feels no torque about
// its centroid (Archimedes acts at the centre of buoyancy) and (centroid - c) x F about any
// other point c; a non-linear dynamic pressure field gives the face-by-face sum computed on the
// CPU, about the centroid and about a given point.
#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <vector>

#include "fluid/grid.h"
#include "force/force_reducer.h"
#include "compute/group_reducer.h"
#include "compute/texture3d.h"
#include "obstacle/classifier.h"
#include "test_util.h"

namespace hf::force {
namespace {

constexpr int kNb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

struct BoxScene {
  fluid::Grid grid;
  glm::ivec3 lo{3, 4, 2}, hi{9, 7, 12};  // solid cells lo..hi-1 (6 x 3 x 10)
  bool solid(int i, int j, int k) const {
    return i >= lo.x && j >= lo.y && k >= lo.z && i < hi.x && j < hi.y && k < hi.z;
  }
  float pressure(int i, int j, int k) const {  // Pa, dynamic part
    return 3.0f * static_cast<float>(i * k) - 2.0f * static_cast<float>(j * j) + 0.5f * static_cast<float>(k * k) + 5.0f;
  }
};

BoxScene makeScene() {
  BoxScene s;
  s.grid.res = glm::ivec3(12, 11, 16);
  s.grid.cell_size_m = 0.02f;
  s.grid.origin_m = glm::vec3(0.3f, -0.2f, 1.0f);
  return s;
}

BodyForce gpuForce(const BoxScene& s, bool dynamic, const glm::vec3& rho_g, const std::optional<glm::vec3>& centre_m) {
  return test::DeviceTest::onGl([&] {
    const fluid::Grid& g = s.grid;
    std::vector<std::uint8_t> mask(g.cells());
    std::vector<float> p(g.cells());
    for (int k = 0; k < g.res.z; ++k)
      for (int j = 0; j < g.res.y; ++j)
        for (int i = 0; i < g.res.x; ++i) {
          const std::size_t n = i + g.res.x * (j + static_cast<std::size_t>(g.res.y) * k);
          mask[n] = s.solid(i, j, k);
          p[n] = dynamic ? s.pressure(i, j, k) : 0.0f;
        }
    compute::Texture3D solid(g.res, compute::TexelFormat::R8UI, "solid");
    compute::Texture3D cls(g.res, compute::TexelFormat::R8UI, "classes");
    compute::Texture3D nbmask(g.res, compute::TexelFormat::R8UI, "nbmask");
    compute::Texture3D pressure(g.res, compute::TexelFormat::R32F, "pressure");
    solid.upload(mask.data(), mask.size());
    pressure.upload(p.data(), p.size() * sizeof(float));
    compute::Texture3D face_open(g.res + 1, compute::TexelFormat::RGBA32F, "face fractions");
    obstacle::Classifier classifier(g);
    classifier.binaryFractions(solid, face_open, obstacle::wholeGrid(g.res));
    classifier.classify(solid, face_open, cls, nbmask, false, obstacle::wholeGrid(g.res));
    ForceReducer reducer(g);
    compute::GroupReducer groups(ForceReducer::partialsNeeded(g), 6);
    const ForceSlots slots{5, 1, 3};  // any slots
    const obstacle::CellBox box{s.lo - 1, s.hi - s.lo + 2};
    const glm::vec3 p0 = g.toWorld(glm::vec3(s.lo + s.hi) * 0.5f) + glm::vec3(0.013f, -0.004f, 0.02f);
    reducer.reduce(pressure, cls, nbmask, face_open, box, false, rho_g, p0, groups, slots);
    return ForceReducer::decode(groups.readResults(), slots, p0, centre_m);
  });
}

class TorqueTest : public test::DeviceTest {};

TEST_F(TorqueTest, HydrostaticTorqueActsAtTheCentroid) {
  const BoxScene s = makeScene();
  const glm::vec3 rho_g(1.5f, -2.0f, -9810.0f);  // N/m^3
  const glm::dvec3 centroid = glm::dvec3(s.grid.toWorld(glm::vec3(s.lo + s.hi) * 0.5f));
  const double volume = 6.0 * 3.0 * 10.0 * std::pow(double(s.grid.cell_size_m), 3);
  const glm::dvec3 buoyancy = -glm::dvec3(rho_g) * volume;
  const double lever = 10.0 * s.grid.cell_size_m;  // size of the body
  const BodyForce about_centroid = gpuForce(s, false, rho_g, std::nullopt);
  EXPECT_EQ(about_centroid.solid_cells, 180);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(about_centroid.centroid_m[a], centroid[a], 1e-5);
    EXPECT_NEAR(about_centroid.torque_centre_m[a], centroid[a], 1e-5);
    EXPECT_NEAR(about_centroid.force_n[a], buoyancy[a], 1e-4 * std::abs(buoyancy.z));
    EXPECT_NEAR(about_centroid.torque_n_m[a], 0.0, 1e-4 * std::abs(buoyancy.z) * lever) << a;
  }
  const glm::vec3 c(0.1f, 0.4f, 1.5f);
  const BodyForce about_c = gpuForce(s, false, rho_g, c);
  const glm::dvec3 want = glm::cross(centroid - glm::dvec3(c), buoyancy);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(about_c.torque_centre_m[a], c[a], 1e-7);
    EXPECT_NEAR(about_c.torque_n_m[a], want[a], 1e-4 * glm::length(want)) << a;
  }
}

TEST_F(TorqueTest, DynamicPressureTorqueIsTheFaceSum) {
  const BoxScene s = makeScene();
  const fluid::Grid& g = s.grid;
  const double area = double(g.cell_size_m) * g.cell_size_m;
  for (const std::optional<glm::vec3> centre : {std::optional<glm::vec3>{}, std::optional<glm::vec3>{glm::vec3(0.2f, 0.1f, 1.1f)}}) {
    const glm::dvec3 c = centre ? glm::dvec3(*centre) : glm::dvec3(g.toWorld(glm::vec3(s.lo + s.hi) * 0.5f));
    glm::dvec3 force(0.0), torque(0.0);
    for (int k = 0; k < g.res.z; ++k)
      for (int j = 0; j < g.res.y; ++j)
        for (int i = 0; i < g.res.x; ++i) {
          if (!s.solid(i, j, k)) continue;
          for (const auto& d : kNb) {
            const glm::ivec3 q(i + d[0], j + d[1], k + d[2]);
            if (s.solid(q.x, q.y, q.z)) continue;
            const glm::dvec3 n(d[0], d[1], d[2]);
            const glm::dvec3 face = glm::dvec3(g.toWorld(glm::vec3(i, j, k) + 0.5f)) + 0.5 * g.cell_size_m * n;
            const glm::dvec3 f = -double(s.pressure(q.x, q.y, q.z)) * area * n;
            force += f;
            torque += glm::cross(face - c, f);
          }
        }
    const BodyForce r = gpuForce(s, true, glm::vec3(0.0f), centre);
    ASSERT_GT(glm::length(torque), 1e-3) << "the field must give a torque";
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(r.force_n[a], force[a], 1e-5 * glm::length(force) + 1e-7);
      EXPECT_NEAR(r.torque_n_m[a], torque[a], 1e-4 * glm::length(torque)) << "axis " << a;
    }
  }
}

}  // namespace
}  // namespace hf::force
