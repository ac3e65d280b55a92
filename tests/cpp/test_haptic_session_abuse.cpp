// SPDX-License-Identifier: GPL-3.0-or-later
// HapticSession against what a user or a device can throw at it: probe speeds at and beyond
// the simulation's limit, pose streams with jumps, far poses and floods, and a second session
// on the same Simulation. Timing is never asserted (generous waits only).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <thread>

#include "common/error.h"
#include "fluid/validate.h"
#include "haptics/devices/host_device.h"
#include "haptics/devices/null_device.h"
#include "session/haptic_session.h"
#include "session/simulation.h"
#include "session/simulation_claim.h"
#include "test_util.h"

namespace hf::haptics {
namespace {

using namespace std::chrono_literals;
using test::waitFor;

session::SimulationConfig smallConfig() {
  session::SimulationConfig cfg;
  cfg.resolution = glm::ivec3(16);
  cfg.params.pressure_iterations = 10;
  return cfg;
}

session::HapticSessionSettings sessionSettings() {
  session::HapticSessionSettings s;
  s.probe_radius_m = 0.15f;
  s.loop.pipeline.map.offset_m = glm::vec3(0.5f);
  s.loop.pipeline.safety.ramp_s = 0.0;
  s.loop.realtime = false;
  return s;
}

// Speeds above the limit are scaled to just under it: every scaled vector is accepted by the
// simulation (scaled to exactly the limit, float rounding left about a third just above it).
TEST(HapticSessionAbuse, ProbeSpeedsBeyondTheLimitAreScaledToOnesTheSimulationAccepts) {
  session::Simulation sim(smallConfig());
  session::HapticSession hs(sim, std::make_shared<HostDevice>(5.0f), sessionSettings());
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> dir(-1.0f, 1.0f);
  std::uniform_real_distribution<float> exponent(3.0f, 38.0f);
  int refused = 0;
  for (int i = 0; i < 2000; ++i) {
    PoseFrame p;
    p.position_m = glm::vec3(0.5f);
    const glm::vec3 d(dir(rng), dir(rng), dir(rng));
    // Magnitudes from the limit up to near float's maximum, plus the limit itself.
    const float speed = i == 0 ? fluid::kMaxProbeSpeed : std::pow(10.0f, exponent(rng));
    p.velocity_m_s = glm::normalize(d) * speed;
    const obstacle::RigidPose pose = hs.poseFor(p);
    EXPECT_LE(glm::length(pose.velocity_m_s), fluid::kMaxProbeSpeed) << i;
    EXPECT_GT(glm::length(pose.velocity_m_s), 0.99f * fluid::kMaxProbeSpeed) << i;  // the direction kept, not zeroed
    try {
      sim.setProbePose(pose);
    } catch (const InvalidArgument&) {
      ++refused;
    }
  }
  EXPECT_EQ(refused, 0);
}

// A running session survives any pose stream: jumps across the domain, poses kilometres away,
// and floods of pushes microseconds apart (speeds of 1e9 m/s). The force stays finite and within
// max_force, and the session is still running afterwards.
TEST(HapticSessionAbuse, ASessionSurvivesAnAbusivePoseStream) {
  session::Simulation sim(smallConfig());
  auto device = std::make_shared<HostDevice>(5.0f);
  session::HapticSessionSettings s = sessionSettings();
  s.max_force_n = 4.0f;
  session::HapticSession hs(sim, device, s);
  device->pushPose(glm::vec3(0.0f), 1.0);
  hs.start();
  std::atomic<bool> done{false};
  std::thread pusher([&] {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    double t = 2.0;
    for (std::uint64_t i = 0; !done.load(); ++i) {
      glm::vec3 p;
      switch (i % 4) {
        case 0: p = glm::vec3(u(rng), u(rng), u(rng)) * 0.5f; break;   // jumps inside the domain
        case 1: p = glm::vec3(u(rng), u(rng), u(rng)) * 1e4f; break;   // far away
        case 2: p = glm::vec3(1e3f, -1e3f, 1e3f); break;               // pressed into a corner
        default: p = glm::vec3(-u(rng), u(rng), -u(rng)) * 0.5f; break;
      }
      t += (i % 16 == 0) ? 1e-2 : 1e-6;  // mostly a flood, microseconds apart
      device->pushPose(p, t);
      if (i % 64 == 0) std::this_thread::sleep_for(1ms);
    }
  });
  const bool stepped = waitFor(
      [&] { return hs.stats().sim_steps >= 40 || hs.state() != session::SessionState::Running; }, 120000ms);
  for (int i = 0; i < 200; ++i) {  // the commanded force meanwhile
    const glm::vec3 f = hs.latest().commanded_n;
    ASSERT_TRUE(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z));
    ASSERT_LE(glm::length(f), 4.0f);
    std::this_thread::sleep_for(1ms);
  }
  done = true;
  pusher.join();
  EXPECT_TRUE(stepped);
  EXPECT_EQ(hs.state(), session::SessionState::Running) << hs.error();
  EXPECT_EQ(hs.error(), "");
  EXPECT_NO_THROW(hs.stop());
  EXPECT_EQ(hs.state(), session::SessionState::Stopped);
}

// One Simulation, one driving session at a time: a second start() is refused while the first
// runs (its probe would jump between the two sessions' poses), and allowed once it stopped.
TEST(HapticSessionAbuse, ASecondSessionOnTheSameSimulationIsRefusedUntilTheFirstStops) {
  session::Simulation sim(smallConfig());
  session::HapticSessionSettings s = sessionSettings();
  session::HapticSession first(sim, std::make_shared<NullDevice>(5.0f), s);
  s.probe_radius_m = std::nullopt;  // keep the probe the first session made
  session::HapticSession second(sim, std::make_shared<NullDevice>(5.0f), s);
  first.start();
  EXPECT_TRUE(session::SimulationClaim::claimed(sim));
  try {
    second.start();
    ADD_FAILURE() << "a second session started on a Simulation already driven";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("another running HapticSession drives it"), std::string::npos) << e.what();
  }
  EXPECT_EQ(second.state(), session::SessionState::Idle);
  // Making one while the first runs is refused too: it would replace the running session's probe.
  EXPECT_THROW(session::HapticSession(sim, std::make_shared<NullDevice>(5.0f), sessionSettings()), Error);
  // Another simulation is free.
  session::Simulation other(smallConfig());
  session::HapticSession elsewhere(other, std::make_shared<NullDevice>(5.0f), sessionSettings());
  EXPECT_NO_THROW(elsewhere.start());
  elsewhere.stop();
  first.stop();
  EXPECT_FALSE(session::SimulationClaim::claimed(sim));
  EXPECT_NO_THROW(second.start());
  ASSERT_TRUE(waitFor([&] { return second.stats().sim_steps >= 2; }, 60000ms));
  second.stop();
  EXPECT_EQ(second.state(), session::SessionState::Stopped);
}

}  // namespace
}  // namespace hf::haptics
