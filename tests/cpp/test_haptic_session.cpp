// SPDX-License-Identifier: GPL-3.0-or-later
// HapticSession over a small simulation: both threads, the probe following the device, and a
// device that goes away. Timing is never asserted tightly (structure and generous bounds).
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "common/error.h"
#include "haptics/devices/host_device.h"
#include "session/haptic_session.h"
#include "session/simulation.h"
#include "test_util.h"

namespace hf::haptics {
namespace {

using namespace std::chrono_literals;

using test::waitFor;

// The whole session over a small simulation: both threads run, the probe follows the device,
// forces come back, and a device that goes away ends the session with its error.
TEST(HapticSession, RunsStopsAndReportsADeviceError) {
  session::SimulationConfig cfg;
  cfg.resolution = glm::ivec3(16);
  cfg.params.pressure_iterations = 20;
  session::Simulation sim(cfg);
  auto device = std::make_shared<HostDevice>(5.0f);
  session::HapticSessionSettings s;
  s.probe_radius_m = 0.15f;
  s.workspace_offset_m = glm::vec3(0.5f);
  s.loop.pipeline.safety.ramp_s = 0.0;
  session::HapticSession hs(sim, device, s);
  // A pose far outside the domain is held inside the region the simulation accepts.
  PoseFrame far;
  far.position_m = glm::vec3(5.0f, 0.5f, -3.0f);
  far.velocity_m_s = glm::vec3(1.0f, 1.0f, 1.0f);
  const obstacle::RigidPose held = hs.poseFor(far);
  EXPECT_LT(held.originM().x, 1.0f - 0.15f);
  EXPECT_GT(held.originM().z, 0.15f);
  EXPECT_EQ(held.originM().y, 0.5f);
  EXPECT_EQ(held.velocity_m_s.x, 0.0f);  // pressed against the wall: no motion along x
  EXPECT_EQ(held.velocity_m_s.y, 1.0f);
  EXPECT_NO_THROW(sim.setProbePose(held));  // right at the edge of what the simulation accepts
  ASSERT_TRUE(sim.sphereProbe().has_value());
  EXPECT_EQ(sim.sphereProbe()->radius_m, 0.15f);

  device->pushPose(glm::vec3(0.0f));
  hs.start();
  EXPECT_THROW(hs.start(), Error);
  ASSERT_TRUE(waitFor([&] { return hs.stats().sim_steps >= 3 && hs.stats().haptic.frames >= 3; }, 60000ms));
  hs.pause();
  EXPECT_EQ(hs.state(), session::SessionState::Paused);
  hs.resume();
  EXPECT_EQ(hs.state(), session::SessionState::Running);
  const auto steps = hs.stats().sim_steps;
  ASSERT_TRUE(waitFor([&] { return hs.stats().sim_steps > steps; }, 60000ms));
  device->close();  // the device goes away under the running session
  ASSERT_TRUE(waitFor([&] { return hs.stats().state == session::SessionState::Failed; }, 10000ms));
  EXPECT_NE(hs.error().find("read after close"), std::string::npos) << hs.error();
  try {
    hs.stop();
    FAIL() << "stop() must raise the error that ended the session";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("read after close"), std::string::npos);
  }
  EXPECT_NO_THROW(hs.stop());  // raised once
  EXPECT_EQ(hs.state(), session::SessionState::Failed);
  EXPECT_EQ(hs.latest().commanded_n, glm::vec3(0.0f));
}

}  // namespace
}  // namespace hf::haptics

namespace hf::haptics {
namespace {

// A mesh probe set on the simulation is kept (orientation and scale) and moved by the device.
TEST(HapticSession, KeepsTheSimulationsMeshProbeAndItsOrientation) {
  session::SimulationConfig cfg;
  cfg.resolution = glm::ivec3(16);
  session::Simulation sim(cfg);
  obstacle::TriangleMesh cube;  // a 0.2 m cube, outward counter-clockwise faces
  for (int i = 0; i < 8; ++i) cube.vertices_m.emplace_back(i & 1 ? 0.1f : -0.1f, i & 2 ? 0.1f : -0.1f, i & 4 ? 0.1f : -0.1f);
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  obstacle::RigidPose start;
  start.transform = glm::mat4(0.0f, 1.0f, 0.0f, 0.0f,   // 90 degrees about z
                              -1.0f, 0.0f, 0.0f, 0.0f,
                              0.0f, 0.0f, 1.0f, 0.0f,
                              0.5f, 0.5f, 0.5f, 1.0f);
  sim.setMeshProbe(cube, start, std::nullopt);
  session::HapticSessionSettings s;
  s.probe_radius_m = std::nullopt;  // keep the simulation's probe
  s.workspace_offset_m = glm::vec3(0.5f);
  session::HapticSession hs(sim, std::make_shared<HostDevice>(5.0f), s);
  PoseFrame p;
  p.position_m = glm::vec3(0.6f, 0.45f, 3.0f);
  p.velocity_m_s = glm::vec3(0.1f, 0.0f, 0.2f);
  const obstacle::RigidPose moved = hs.poseFor(p);
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) EXPECT_EQ(moved.transform[c][r], start.transform[c][r]);
  }
  EXPECT_NEAR(moved.originM().x, 0.6f, 1e-6f);
  EXPECT_NEAR(moved.originM().y, 0.45f, 1e-6f);
  EXPECT_LT(moved.originM().z, 1.0f - 0.1f - 0.0625f + 1e-4f);  // held one cell below the lid
  EXPECT_EQ(moved.velocity_m_s.z, 0.0f);
  EXPECT_NO_THROW(sim.setProbePose(moved));
  ASSERT_TRUE(sim.probe().has_value());
  EXPECT_EQ(sim.probe()->kind, session::ProbeState::Kind::Mesh);
}

}  // namespace
}  // namespace hf::haptics
