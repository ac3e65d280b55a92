// SPDX-License-Identifier: GPL-3.0-or-later
// SphereProbe::voxelize + Classifier::classify against a CPU reference of the rules, cell by
// cell: solid mask, rigid velocity, the four cell classes and the neighbour mask.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <vector>

#include "fluid/grid.h"
#include "compute/texture3d.h"
#include "obstacle/cell_class.h"
#include "obstacle/classifier.h"
#include "obstacle/sphere_probe.h"
#include "test_util.h"

namespace hf::obstacle {
namespace {

constexpr int kNb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
constexpr std::uint8_t kOpenTopBit = 64;
constexpr std::uint8_t kSolidBit = 128;

struct Scene {
  glm::vec3 centre_cells;  // sphere centre in grid units
  float radius_cells;
  bool open_top;
};

struct GpuResult {
  std::vector<std::uint8_t> solid, cls, nbmask;
  std::vector<float> velocity;  // RGBA per cell
};

struct Reference {
  std::vector<std::uint8_t> solid, cls, nbmask;
  std::vector<glm::vec3> velocity;
};

class ClassifierTest : public test::DeviceTest {
 protected:
  static fluid::Grid grid() {
    fluid::Grid g;
    g.res = glm::ivec3(24, 24, 24);
    g.cell_size_m = 0.04f;
    g.origin_m = glm::vec3(0.2f, -0.1f, 0.05f);
    return g;
  }

  static SpherePose poseFor(const fluid::Grid& g, const Scene& s) {
    SpherePose p;
    p.centre_m = g.toWorld(s.centre_cells);
    p.radius_m = s.radius_cells * g.cell_size_m;
    p.velocity_m_s = glm::vec3(0.3f, -0.2f, 0.1f);
    p.angular_velocity_rad_s = glm::vec3(1.0f, 2.0f, -3.0f);
    return p;
  }

  // Everything the GPU wrote, for each scene in turn, reusing the same textures (so a scene
  // must also overwrite what the one before it left).
  static std::vector<GpuResult> runGpu(const fluid::Grid& g, const std::vector<Scene>& scenes) {
    return onGl([&] {
      compute::Texture3D solid(g.res, compute::TexelFormat::R8UI, "solid");
      compute::Texture3D velocity(g.res, compute::TexelFormat::RGBA32F, "solid velocity");
      compute::Texture3D cls(g.res, compute::TexelFormat::R8UI, "classes");
      compute::Texture3D nbmask(g.res, compute::TexelFormat::R8UI, "nbmask");
      compute::Texture3D face_open(g.res + 1, compute::TexelFormat::RGBA32F, "face fractions");
      SphereProbe probe(g);
      Classifier classifier(g);
      std::vector<GpuResult> out;
      for (const Scene& s : scenes) {
        probe.setPose(poseFor(g, s));
        probe.voxelize(solid, velocity, obstacle::wholeGrid(g.res));
        classifier.binaryFractions(solid, face_open, obstacle::wholeGrid(g.res));
        classifier.classify(solid, face_open, cls, nbmask, s.open_top, obstacle::wholeGrid(g.res));
        GpuResult r;
        r.solid.resize(g.cells());
        r.cls.resize(g.cells());
        r.nbmask.resize(g.cells());
        r.velocity.resize(g.cells() * 4);
        solid.download(r.solid.data(), r.solid.size());
        cls.download(r.cls.data(), r.cls.size());
        nbmask.download(r.nbmask.data(), r.nbmask.size());
        velocity.download(r.velocity.data(), r.velocity.size() * sizeof(float));
        out.push_back(std::move(r));
      }
      return out;
    });
  }

  // The rules, computed on the CPU from the same float centre/radius the probe passes on.
  static Reference reference(const fluid::Grid& g, const Scene& s) {
    const SpherePose pose = poseFor(g, s);
    const glm::vec3 c = g.toGrid(pose.centre_m);
    const float r = pose.radius_m / g.cell_size_m;
    const glm::ivec3 n = g.res;
    auto index = [&](int i, int j, int k) { return static_cast<std::size_t>(i + n.x * (j + n.y * k)); };
    auto inGrid = [&](int i, int j, int k) { return i >= 0 && j >= 0 && k >= 0 && i < n.x && j < n.y && k < n.z; };
    Reference ref;
    ref.solid.assign(g.cells(), 0);
    ref.cls.assign(g.cells(), 0);
    ref.nbmask.assign(g.cells(), 0);
    ref.velocity.assign(g.cells(), glm::vec3(0.0f));
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const glm::vec3 d = glm::vec3(i, j, k) + 0.5f - c;
          const double d2 = glm::dot(glm::dvec3(d), glm::dvec3(d));
          // The scenes keep every cell centre clear of the sphere's surface, so float
          // rounding on the GPU cannot flip a cell.
          EXPECT_GT(std::abs(d2 - double(r) * double(r)), 1e-3) << "scene too close to a cell centre";
          // The rigid velocity at every cell centre (cut faces outside the body's cells use it).
          ref.velocity[index(i, j, k)] = pose.velocity_m_s + glm::cross(pose.angular_velocity_rad_s, d * g.cell_size_m);
          if (d2 <= double(r) * double(r)) ref.solid[index(i, j, k)] = 1;
        }
    for (int k = 0; k < n.z; ++k)
      for (int j = 0; j < n.y; ++j)
        for (int i = 0; i < n.x; ++i) {
          const bool solid = ref.solid[index(i, j, k)] != 0;
          bool fluid_nb = false, solid_nb = false;
          // Links across the open faces (binary fractions: neither side solid); no link: no unknown.
          std::uint8_t mask = 0;
          for (int dir = 0; dir < 6; ++dir) {
            const int a = i + kNb[dir][0], b = j + kNb[dir][1], cc = k + kNb[dir][2];
            if (!inGrid(a, b, cc)) {
              if (dir == 5 && s.open_top && !solid) mask |= kOpenTopBit;
              continue;
            }
            if (ref.solid[index(a, b, cc)] != 0) {
              solid_nb = true;
            } else {
              fluid_nb = true;
              if (!solid) mask |= static_cast<std::uint8_t>(1u << dir);
            }
          }
          if (mask == 0) mask = kSolidBit;
          CellClass cls = solid ? (fluid_nb ? CellClass::Boundary : CellClass::Inside)
                                : (solid_nb ? CellClass::Surrounding : CellClass::Outside);
          ref.cls[index(i, j, k)] = static_cast<std::uint8_t>(cls);
          ref.nbmask[index(i, j, k)] = mask;
        }
    return ref;
  }

  static std::array<int, 4> classCounts(const std::vector<std::uint8_t>& cls) {
    std::array<int, 4> n{};
    for (auto c : cls) {
      if (c < 4) ++n[c];
    }
    return n;
  }

  // Compares every cell; reports at most a few mismatches per field.
  static void expectMatches(const fluid::Grid& g, const GpuResult& gpu, const Reference& ref) {
    int bad_solid = 0, bad_cls = 0, bad_mask = 0, bad_vel = 0;
    for (std::size_t n = 0; n < g.cells(); ++n) {
      const int i = static_cast<int>(n % g.res.x);
      const int j = static_cast<int>((n / g.res.x) % g.res.y);
      const int k = static_cast<int>(n / (static_cast<std::size_t>(g.res.x) * g.res.y));
      std::ostringstream at;
      at << " at cell (" << i << ", " << j << ", " << k << ")";
      if (gpu.solid[n] != ref.solid[n] && bad_solid++ < 5)
        ADD_FAILURE() << "solid " << int(gpu.solid[n]) << " != " << int(ref.solid[n]) << at.str();
      if (gpu.cls[n] != ref.cls[n] && bad_cls++ < 5)
        ADD_FAILURE() << "class " << int(gpu.cls[n]) << " != " << int(ref.cls[n]) << at.str();
      if (gpu.nbmask[n] != ref.nbmask[n] && bad_mask++ < 5)
        ADD_FAILURE() << "nbmask " << int(gpu.nbmask[n]) << " != " << int(ref.nbmask[n]) << at.str();
      for (int a = 0; a < 3; ++a) {
        if (std::abs(gpu.velocity[4 * n + a] - ref.velocity[n][a]) > 1e-5f && bad_vel++ < 5)
          ADD_FAILURE() << "velocity[" << a << "] " << gpu.velocity[4 * n + a] << " != " << ref.velocity[n][a] << at.str();
      }
    }
    EXPECT_EQ(bad_solid + bad_cls + bad_mask + bad_vel, 0);
  }
};

TEST_F(ClassifierTest, SphereInsideTheGridMatchesTheRulesEverywhere) {
  const fluid::Grid g = grid();
  const Scene scene{glm::vec3(12.3f, 11.7f, 12.1f), 6.37f, false};
  const auto gpu = runGpu(g, {scene});
  const Reference ref = reference(g, scene);
  expectMatches(g, gpu[0], ref);
  const auto counts = classCounts(ref.cls);
  for (int c = 0; c < 4; ++c) EXPECT_GT(counts[c], 0) << "class " << c << " missing from the scene";
  // About (4/3) pi r^3 solid cells.
  const double solid = counts[2] + counts[3];
  EXPECT_NEAR(solid, 4.0 / 3.0 * M_PI * std::pow(6.37, 3), 0.05 * solid);
}

TEST_F(ClassifierTest, ScenesInTurnOverwriteTheLastOneIncludingSpheresCutByTheGrid) {
  const fluid::Grid g = grid();
  const std::vector<Scene> scenes = {
      {glm::vec3(12.3f, 11.7f, 12.1f), 6.37f, false},
      // Cut by three faces of the grid near a corner: solid cells on the walls whose only
      // non-solid neighbours lie outside the grid are Inside, not Boundary.
      {glm::vec3(2.2f, 21.6f, 1.4f), 5.3f, false},
      // Reaching the open top: every top cell, solid or not, carries the open-top bit.
      {glm::vec3(12.15f, 11.9f, 21.8f), 4.63f, true},
      {glm::vec3(5.45f, 17.9f, 8.2f), 1.21f, true},  // a small sphere: a handful of cells
  };
  const auto gpu = runGpu(g, scenes);
  ASSERT_EQ(gpu.size(), scenes.size());
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    SCOPED_TRACE("scene " + std::to_string(s));
    const Reference ref = reference(g, scenes[s]);
    expectMatches(g, gpu[s], ref);
  }
  // The cut sphere really has cells on the z = 0 wall classed Inside by the in-grid rule.
  const Reference cut = reference(g, scenes[1]);
  int inside_on_wall = 0;
  for (std::size_t n = 0; n < static_cast<std::size_t>(g.res.x * g.res.y); ++n) {
    inside_on_wall += cut.cls[n] == static_cast<std::uint8_t>(CellClass::Inside);
  }
  EXPECT_GT(inside_on_wall, 0);
}

}  // namespace
}  // namespace hf::obstacle
