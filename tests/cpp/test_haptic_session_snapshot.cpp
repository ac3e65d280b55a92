// SPDX-License-Identifier: GPL-3.0-or-later
// HapticSession's field snapshots (the simulation thread reads the fields back after its step;
// the host takes the newest without the GPU) and the settings the session derives for the loop.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include "common/error.h"
#include "haptics/devices/host_device.h"
#include "session/haptic_session.h"
#include "session/simulation.h"
#include "test_util.h"

namespace hf::session {
namespace {

using namespace std::chrono_literals;
using test::waitFor;

SimulationConfig smallConfig() {
  SimulationConfig cfg;
  cfg.resolution = glm::ivec3(16);
  cfg.params.pressure_iterations = 10;
  return cfg;
}

// With snapshot_interval_s = 0 every step publishes density and temperature; the sequence
// counts up, and after stop() the newest snapshot holds exactly the fields of the last step.
TEST(HapticSessionSnapshot, PublishesTheFieldsOfEveryStep) {
  Simulation sim(smallConfig());
  fluid::SmokeSource src;
  src.enabled = true;
  src.centre_m = glm::vec3(0.5f, 0.5f, 0.2f);
  src.radius_m = 0.15f;
  src.density = 1.0f;
  src.temperature_k = 5.0f;
  sim.setSmokeSource(src);
  auto device = std::make_shared<haptics::HostDevice>(5.0f);
  device->pushPose(glm::vec3(0.0f));
  HapticSessionSettings s;
  s.probe_radius_m = 0.1f;
  s.snapshot_interval_s = 0.0;
  s.snapshot_temperature = true;
  s.sim_dt_s = 0.01;
  HapticSession hs(sim, device, s);
  EXPECT_EQ(hs.fieldSnapshot(), nullptr);  // nothing before the first step
  hs.start();
  ASSERT_TRUE(waitFor([&] { return hs.fieldSnapshot() && hs.fieldSnapshot()->sequence >= 3; }, 60000ms));
  const auto first = hs.fieldSnapshot();
  ASSERT_TRUE(waitFor([&] { return hs.fieldSnapshot()->sequence > first->sequence; }, 60000ms));
  EXPECT_GT(hs.fieldSnapshot()->steps, first->steps);
  hs.stop();
  const auto last = hs.fieldSnapshot();
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(last->resolution, glm::ivec3(16));
  EXPECT_EQ(static_cast<std::uint64_t>(last->steps), hs.stats().sim_steps);  // one per step
  EXPECT_EQ(last->sequence, hs.stats().snapshots);
  EXPECT_EQ(last->steps, sim.steps());
  EXPECT_DOUBLE_EQ(last->time_s, sim.timeS());
  EXPECT_EQ(last->density, sim.readFloat(Field::Density));
  EXPECT_EQ(last->temperature, sim.readFloat(Field::Temperature));
  // The emitter's centre cell (8, 8, 3) holds the source's density.
  EXPECT_NEAR(last->density[8 + 16 * (8 + 16 * 3)], 1.0f, 1e-3f);
  EXPECT_NEAR(last->temperature[8 + 16 * (8 + 16 * 3)], 5.0f, 1e-3f);
}

// fieldSnapshot() returns while another thread's long step holds the GPU (it never waits on it).
TEST(HapticSessionSnapshot, ReturnsWhileALongStepHoldsTheGpu) {
  Simulation sim(smallConfig());
  auto device = std::make_shared<haptics::HostDevice>(5.0f);
  device->pushPose(glm::vec3(0.0f));
  HapticSessionSettings s;
  s.snapshot_interval_s = 0.0;
  HapticSession hs(sim, device, s);
  hs.start();
  ASSERT_TRUE(waitFor([&] { return hs.fieldSnapshot() != nullptr; }, 60000ms));
  sim.updateParams([](fluid::FluidParams& p) { p.pressure_iterations = 10000; });
  std::atomic<bool> started{false}, done{false};
  std::thread long_step([&] {
    started = true;
    sim.step(0.01);
    done = true;
  });
  while (!started) std::this_thread::sleep_for(1ms);
  std::this_thread::sleep_for(50ms);  // let the step take the GPU lock
  ASSERT_FALSE(done.load()) << "the step finished too soon for this check";
  const auto snap = hs.fieldSnapshot();
  EXPECT_FALSE(done.load()) << "fieldSnapshot() waited for the GPU step";
  ASSERT_NE(snap, nullptr);
  EXPECT_EQ(snap->density.size(), std::size_t{16 * 16 * 16});
  EXPECT_TRUE(snap->temperature.empty());  // not asked for
  long_step.join();
  hs.stop(120.0);
}

// The settings the bindings used to compute: centred workspace, cutoff bound, trace size.
TEST(HapticSessionSettings, ResolvesTheLoopsDerivedSettings) {
  haptics::DeviceInfo info;
  info.workspace_min_m = glm::vec3(-0.05f, -0.05f, 0.07f);
  info.workspace_max_m = glm::vec3(0.05f, 0.05f, 0.17f);
  info.max_force_n = 8.0f;
  HapticSessionSettings s;
  s.loop.pipeline.map.scale = glm::vec3(4.0f, 4.0f, -2.0f);
  s.loop.rate_hz = 500.0;
  s.trace = true;
  s.trace_s = 3.0;
  const HapticSessionSettings r = s.resolve(glm::vec3(1.0f, 0.0f, 0.0f), glm::vec3(2.0f, 1.0f, 1.0f), info);
  // The workspace's middle (0, 0, 0.12) lands on the domain's centre (2, 0.5, 0.5).
  const glm::vec3 mid = r.loop.pipeline.map.positionToDomain(glm::vec3(0.0f, 0.0f, 0.12f));
  EXPECT_NEAR(mid.x, 2.0f, 1e-6f);
  EXPECT_NEAR(mid.y, 0.5f, 1e-6f);
  EXPECT_NEAR(mid.z, 0.5f, 1e-6f);
  EXPECT_DOUBLE_EQ(r.loop.pipeline.filter.max_cutoff_hz, 100.0);  // 0.2 x 500 Hz
  EXPECT_EQ(r.loop.trace_capacity, std::size_t{1501});
  s.workspace_offset_m = glm::vec3(0.1f, 0.2f, 0.3f);
  EXPECT_EQ(s.resolve(glm::vec3(0.0f), glm::vec3(1.0f), info).loop.pipeline.map.offset_m, glm::vec3(0.1f, 0.2f, 0.3f));
  s.snapshot_interval_s = -1.0;
  EXPECT_THROW(s.resolve(glm::vec3(0.0f), glm::vec3(1.0f), info), InvalidArgument);
  s.snapshot_interval_s = std::nullopt;
  s.max_cutoff_per_rate = 0.7;  // above Nyquist
  EXPECT_THROW(s.resolve(glm::vec3(0.0f), glm::vec3(1.0f), info), InvalidArgument);
}

}  // namespace
}  // namespace hf::session
