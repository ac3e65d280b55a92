// SPDX-License-Identifier: GPL-3.0-or-later
// StepPipeline's probe region: a step that redoes only the cells the probe's move can change
// leaves every field the same to the bit as a step that redoes the whole grid, through moves,
// jumps, radius changes, the walls, cut cells and the open top switched, the probe removed and
// put back, a mesh probe moving and jumping with and without cut cells; and it launches less.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "fluid/grid.h"
#include "gl/gl_check.h"
#include "mesh_shapes.h"
#include "obstacle/obstacle.h"
#include "obstacle/triangle_mesh.h"
#include "session/step_pipeline.h"
#include "test_util.h"

namespace hf::session {
namespace {

class ProbeRegionTest : public test::DeviceTest {};

fluid::Grid grid() {
  fluid::Grid g;
  g.res = glm::ivec3(28, 24, 20);
  g.cell_size_m = 1.0f / 28.0f;
  return g;
}

// One step's inputs: a sphere at `centre` (m) moving at `velocity`, or a box mesh, or nothing.
struct Move {
  enum class Probe { None, Sphere, Mesh } probe = Probe::Sphere;
  glm::vec3 centre_m{0.5f};
  float radius_m = 0.12f;
  glm::vec3 velocity_m_s{0.0f};
  bool cut_cells = true;
  bool open_top = true;
};

StepInputs inputs(const Move& m, const std::shared_ptr<const obstacle::TriangleMesh>& mesh) {
  StepInputs in;
  in.dt_s = 1.0f / 30.0f;
  in.params.cut_cells = m.cut_cells;
  in.params.open_top = m.open_top;
  in.params.pressure_iterations = 6;
  in.source.enabled = true;
  in.source.centre_m = glm::vec3(0.5f, 0.4f, 0.12f);
  in.source.radius_m = 0.08f;
  in.source.temperature_k = 5.0f;
  in.rho_g = glm::vec3(0.0f, 0.0f, -9.81f * in.params.density_kg_m3);
  if (m.probe == Move::Probe::Sphere) {
    ProbeState p;
    p.kind = ProbeState::Kind::Sphere;
    p.sphere.centre_m = m.centre_m;
    p.sphere.radius_m = m.radius_m;
    p.sphere.velocity_m_s = m.velocity_m_s;
    p.sphere.angular_velocity_rad_s = glm::vec3(0.0f, 0.0f, 2.0f);
    in.probe = p;
  } else if (m.probe == Move::Probe::Mesh) {
    ProbeState p;
    p.kind = ProbeState::Kind::Mesh;
    p.mesh = mesh;
    p.extent = obstacle::meshExtent(*mesh);
    p.pose.transform = glm::translate(glm::mat4(1.0f), m.centre_m);
    p.pose.velocity_m_s = m.velocity_m_s;
    in.probe = p;
  }
  return in;
}

std::vector<std::uint8_t> bytes(const compute::Texture3D& t) {
  std::vector<std::uint8_t> out(t.texels() * t.bytesPerTexel());
  t.download(out.data(), out.size());
  return out;
}

// Every field a step leaves, but the rigid velocity (only read beside covered faces: compared in
// the probe's bounds below).
std::vector<std::pair<std::string, std::vector<std::uint8_t>>> fields(fluid::FluidFields& f) {
  return {{"solid", bytes(f.solid)},
          {"face_open", bytes(f.face_open)},
          {"cell_class", bytes(f.cell_class)},
          {"nbmask", bytes(f.nbmask)},
          {"vel_x", bytes(f.vel[0].cur())},
          {"vel_y", bytes(f.vel[1].cur())},
          {"vel_z", bytes(f.vel[2].cur())},
          {"density", bytes(f.density.cur())},
          {"temperature", bytes(f.temperature.cur())},
          {"pressure", bytes(f.pressure.cur())}};
}

// The rigid velocity (RGBA32F) of the cells of `box`.
std::vector<float> solidVelocityIn(fluid::FluidFields& f, const obstacle::CellBox& box, const glm::ivec3& res) {
  std::vector<float> all(f.solid_velocity.texels() * 4);
  f.solid_velocity.download(all.data(), all.size() * sizeof(float));
  std::vector<float> out;
  for (int k = box.origin.z; k < box.origin.z + box.extent.z; ++k)
    for (int j = box.origin.y; j < box.origin.y + box.extent.y; ++j)
      for (int i = box.origin.x; i < box.origin.x + box.extent.x; ++i)
        for (int c = 0; c < 4; ++c) out.push_back(all[4 * (i + res.x * (j + static_cast<std::size_t>(res.y) * k)) + c]);
  return out;
}

TEST_F(ProbeRegionTest, LimitedStepsEqualWholeGridStepsToTheBit) {
  const fluid::Grid g = grid();
  auto mesh = std::make_shared<const obstacle::TriangleMesh>(test::boxMesh(glm::vec3(-0.1f), glm::vec3(0.1f)));
  using P = Move::Probe;
  std::vector<Move> moves;
  // A sweep along x with a changing speed, then up and down, with cut cells.
  for (int s = 0; s < 6; ++s) {
    Move m;
    m.centre_m = glm::vec3(0.3f + 0.05f * s * (1.0f + 0.2f * s), 0.45f, 0.4f + 0.01f * s);
    m.velocity_m_s = glm::vec3(0.6f, 0.0f, 0.1f);
    moves.push_back(m);
  }
  Move jump;  // a jump across the domain, a smaller sphere
  jump.centre_m = glm::vec3(0.2f, 0.2f, 0.5f);
  jump.radius_m = 0.07f;
  moves.push_back(jump);
  Move wall = jump;  // against the -x and -y walls and near the floor
  wall.centre_m = glm::vec3(0.05f, 0.04f, 0.1f);
  moves.push_back(wall);
  moves.push_back(wall);  // still
  Move binary = wall;  // cut cells off, then moving without them
  binary.cut_cells = false;
  moves.push_back(binary);
  binary.centre_m = glm::vec3(0.15f, 0.1f, 0.2f);
  moves.push_back(binary);
  Move closed = binary;  // the top closed, moving
  closed.open_top = false;
  moves.push_back(closed);
  closed.centre_m += glm::vec3(0.03f, 0.02f, 0.01f);
  moves.push_back(closed);
  Move none = closed;  // no probe for two steps
  none.probe = P::None;
  moves.push_back(none);
  moves.push_back(none);
  Move back;  // back, with cut cells, near the +x+y corner and the top
  back.centre_m = glm::vec3(0.9f, 0.75f, 0.6f);
  moves.push_back(back);
  back.centre_m = glm::vec3(0.88f, 0.76f, 0.62f);
  moves.push_back(back);
  Move box;  // a mesh probe moving, its cut cells off then on, then the sphere again
  box.probe = P::Mesh;
  box.centre_m = glm::vec3(0.5f, 0.4f, 0.4f);
  box.velocity_m_s = glm::vec3(0.0f, 0.5f, 0.2f);
  box.cut_cells = false;
  moves.push_back(box);
  box.centre_m = glm::vec3(0.5f, 0.43f, 0.41f);
  moves.push_back(box);
  box.cut_cells = true;
  moves.push_back(box);
  box.centre_m = glm::vec3(0.52f, 0.47f, 0.43f);
  moves.push_back(box);
  box.centre_m = glm::vec3(0.25f, 0.6f, 0.3f);  // a jump
  moves.push_back(box);
  Move after;
  after.centre_m = glm::vec3(0.45f, 0.45f, 0.45f);
  moves.push_back(after);
  after.centre_m = glm::vec3(0.5f, 0.45f, 0.45f);
  moves.push_back(after);

  onGl([&] {
    StepPipeline limited(g), whole(g);
    whole.setLimitToProbeMoves(false);
    for (std::size_t s = 0; s < moves.size(); ++s) {
      const StepInputs in = inputs(moves[s], mesh);
      const StepReport a = limited.step(in);
      const StepReport b = whole.step(in);
      const auto fa = fields(limited.fields());
      const auto fb = fields(whole.fields());
      for (std::size_t i = 0; i < fa.size(); ++i) {
        ASSERT_TRUE(fa[i].second == fb[i].second) << "step " << s << ": " << fa[i].first << " differs";
      }
      EXPECT_EQ(std::memcmp(&a.force_n, &b.force_n, sizeof(a.force_n)), 0) << "step " << s;
      if (moves[s].probe == P::Sphere) {
        obstacle::SphereProbe probe(g);
        probe.setPose(in.probe->sphere);
        const obstacle::CellBox near = obstacle::grownBox(probe.bounds(), 1, g.res);
        EXPECT_EQ(solidVelocityIn(limited.fields(), near, g.res), solidVelocityIn(whole.fields(), near, g.res))
            << "step " << s;
      }
    }
  });
}

TEST_F(ProbeRegionTest, AMovingSphereStepLaunchesLessThanTheWholeGridStep) {
  const fluid::Grid g = grid();
  Move m;
  onGl([&] {
    StepPipeline limited(g), whole(g);
    whole.setLimitToProbeMoves(false);
    for (StepPipeline* p : {&limited, &whole}) p->step(inputs(m, nullptr));  // the first step: whole grid
    m.centre_m += glm::vec3(0.02f, 0.0f, 0.0f);
    const StepInputs in = inputs(m, nullptr);
    const auto c0 = compute::dispatchCounters();
    limited.step(in);
    const auto c1 = compute::dispatchCounters();
    whole.step(in);
    const auto c2 = compute::dispatchCounters();
    const std::uint64_t saved = (c2.invocations - c1.invocations) - (c1.invocations - c0.invocations);
    // voxelize, the sphere's face fractions and classify: three passes over the grid (or its
    // faces) the limited step makes over a region of about 14^3 cells instead.
    EXPECT_GE(saved, 2 * g.cells()) << "limited " << (c1.invocations - c0.invocations) << ", whole "
                                     << (c2.invocations - c1.invocations);
  });
}

}  // namespace
}  // namespace hf::session
