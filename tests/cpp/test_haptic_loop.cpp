// SPDX-License-Identifier: GPL-3.0-or-later
// The 1 kHz HapticLoop on its thread, with stand-ins for the simulation. Timing is
// never asserted tightly (a loaded 2-core machine): structure and generous bounds only.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "common/error.h"
#include "haptics/devices/device_claim.h"
#include "haptics/devices/host_device.h"
#include "haptics/devices/null_device.h"
#include "haptics/devices/scripted_device.h"
#include "haptics/falcon/falcon.h"
#include "haptics/handoff/clock.h"
#include "haptics/loop/haptic_loop.h"
#include "test_common.h"

namespace hf::haptics {
namespace {

using namespace std::chrono_literals;

// A device that fails on a chosen read and records every force it is given.
class FaultyDevice : public Device {
 public:
  explicit FaultyDevice(int fail_at_read) : fail_at_(fail_at_read) {}
  DeviceInfo info() const override {
    DeviceInfo i;
    i.name = "faulty";
    i.kind = "test";
    i.max_force_n = 4.0f;
    return i;
  }
  DeviceState read() override {
    if (++reads_ >= fail_at_) {
      failed_ = true;
      throw Error("faulty device: cable pulled");
    }
    DeviceState s;
    s.homed = true;
    s.time_s = monotonicNowS();
    return s;
  }
  void writeForce(const glm::vec3& f) override {
    std::lock_guard<std::mutex> lock(mutex_);
    forces_.push_back(f);
    after_failure_.push_back(failed_);
  }
  void close() override {}
  std::vector<glm::vec3> forces() {
    std::lock_guard<std::mutex> lock(mutex_);
    return forces_;
  }
  std::vector<bool> afterFailure() {
    std::lock_guard<std::mutex> lock(mutex_);
    return after_failure_;
  }

 private:
  int fail_at_;
  std::atomic<int> reads_{0};
  std::atomic<bool> failed_{false};
  std::mutex mutex_;
  std::vector<glm::vec3> forces_;
  std::vector<bool> after_failure_;
};

HapticLoopSettings loopSettings() {
  HapticLoopSettings s;
  s.pipeline.safety.max_force_n = 2.0f;  // at most every test device's maximum
  s.pipeline.safety.ramp_s = 0.0;
  s.pipeline.safety.slew_rate_n_s = 1e5f;
  s.pipeline.filter.enabled = false;
  s.trace_capacity = 100000;
  return s;
}

// loopSettings() with a quick stale-force fade: a force older than 0.05 s fades over 0.05 s.
HapticLoopSettings fadingSettings() {
  HapticLoopSettings s = loopSettings();
  s.pipeline.safety.stale_after_s = 0.05;
  s.pipeline.safety.fade_s = 0.05;
  return s;
}

using test::waitFor;

TEST(HapticLoop, RunsPublishesPosesAndBoundsTheForce) {
  auto device = std::make_shared<ScriptedDevice>(std::vector<double>{0.0, 1.0},
                                                 std::vector<glm::vec3>{glm::vec3(0.0f), glm::vec3(0.01f, 0.0f, 0.0f)},
                                                 true, 2.0f);
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  HapticLoopSettings s = loopSettings();
  s.pipeline.map.offset_m = glm::vec3(0.5f);
  s.pipeline.map.scale = glm::vec3(10.0f);
  s.pipeline.map.force_gain = 10.0f;  // 1 N of fluid force asks for 10 N: the device's 2 N bounds it
  HapticLoop loop(device, poses, forces, s);
  loop.start();
  EXPECT_THROW(loop.start(), Error);
  std::atomic<bool> stop_feeder{false};
  std::thread feeder([&] {  // a stand-in simulation at ~100 Hz
    while (!stop_feeder) {
      PoseFrame p;
      ForceFrame f;
      if (poses.tryRead(p)) f.pose_time_s = p.time_s;
      f.force_n = glm::vec3(1.0f, 0.0f, 0.0f);
      f.publish_time_s = monotonicNowS();
      f.sim_rate_hz = 100.0;
      forces.write(f);
      std::this_thread::sleep_for(10ms);
    }
  });
  ASSERT_TRUE(waitFor([&] { return loop.stats().frames >= 5 && loop.stats().ticks >= 50; }, 10000ms));
  // Its pace, against its own clock over the same half second: every deadline of the period is
  // either run or counted as skipped (a loaded machine moves periods from one to the other, a
  // loop that ran late without counting would fall short), and it never runs ahead of its clock.
  const LoopStats before = loop.stats();
  const double t0 = monotonicNowS();
  std::this_thread::sleep_for(500ms);
  const LoopStats after = loop.stats();
  const double deadlines = (monotonicNowS() - t0) * s.rate_hz;
  const double counted = static_cast<double>((after.ticks + after.skipped) - (before.ticks + before.skipped));
  stop_feeder = true;
  feeder.join();
  loop.stop();
  EXPECT_FALSE(loop.running());
  EXPECT_FALSE(loop.failed());
  PoseFrame pose;
  ASSERT_TRUE(poses.tryRead(pose));
  EXPECT_NEAR(pose.position_m.y, 0.5f, 1e-6f);  // mapped into the domain
  EXPECT_GE(pose.position_m.x, 0.5f);
  EXPECT_LE(pose.position_m.x, 0.6f + 1e-6f);
  std::vector<TraceSample> trace;
  loop.drainTrace(trace);
  ASSERT_FALSE(trace.empty());
  float largest = 0.0f;
  for (const auto& t : trace) largest = std::max(largest, glm::length(t.commanded_n));
  EXPECT_LE(largest, 2.0f);
  EXPECT_GT(largest, 1.9f);
  EXPECT_EQ(device->lastForce(), glm::vec3(0.0f));  // the last command on stop is zero
  const LoopStats st = loop.stats();
  EXPECT_GE(counted, 0.9 * deadlines) << after.ticks << " ticks, " << after.skipped << " skipped";
  EXPECT_LE(counted, deadlines + 2.0);
  EXPECT_LE(st.rate_hz, 1.05 * s.rate_hz);  // 1 / mean period: never ahead of the clock
  EXPECT_GT(st.latency_ms.count, 0u);
  EXPECT_GE(st.jitter_ms.max, st.jitter_ms.p99);
  EXPECT_GE(st.jitter_ms.p99, st.jitter_ms.p50);
  EXPECT_TRUE(st.realtime || !st.scheduling.empty());  // granted, or a warning says why not
}

TEST(HapticLoop, DeviceErrorStopsForceAndIsReported) {
  auto device = std::make_shared<FaultyDevice>(200);
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  ForceFrame f;
  f.force_n = glm::vec3(0.0f, 1.5f, 0.0f);
  f.publish_time_s = 1e300;  // never stale
  forces.write(f);
  HapticLoop loop(device, poses, forces, loopSettings());
  loop.start();
  ASSERT_TRUE(waitFor([&] { return !loop.running(); }, 30000ms));
  EXPECT_TRUE(loop.failed());
  EXPECT_NE(loop.error().find("cable pulled"), std::string::npos) << loop.error();
  EXPECT_NE(loop.stats().error.find("cable pulled"), std::string::npos);
  const auto forces_seen = device->forces();
  const auto after = device->afterFailure();
  ASSERT_GE(forces_seen.size(), 100u);
  EXPECT_NEAR(forces_seen[150].y, 1.5f, 1e-5f);  // it was commanding force before the fault
  for (std::size_t i = 0; i < forces_seen.size(); ++i) {
    if (after[i]) {
      EXPECT_EQ(forces_seen[i], glm::vec3(0.0f)) << "command " << i << " after the fault";
    }
  }
  EXPECT_TRUE(after.back());  // a last zero was sent after the fault
  EXPECT_EQ(loop.latest().commanded_n, glm::vec3(0.0f));
  loop.stop();  // harmless after a failure
}

TEST(HapticLoop, StalledSimulationFadesTheCommandToZero) {
  auto device = std::make_shared<HostDevice>(5.0f);
  device->pushPose(glm::vec3(0.0f));
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  HapticLoop loop(device, poses, forces, fadingSettings());
  ForceFrame f;
  f.force_n = glm::vec3(0.0f, 0.0f, -2.0f);
  f.publish_time_s = monotonicNowS();  // published once, then the "simulation" stalls
  forces.write(f);
  loop.start();
  ASSERT_TRUE(waitFor([&] { return loop.stats().ticks > 0; }, 10000ms));
  // Once older than 0.1 s (stale 0.05 + fade 0.05) nothing may be commanded.
  std::this_thread::sleep_for(200ms);
  ASSERT_TRUE(waitFor([&] { return device->lastForce() == glm::vec3(0.0f); }, 10000ms));
  std::vector<TraceSample> trace;
  loop.drainTrace(trace);
  loop.stop();
  ASSERT_FALSE(trace.empty());
  for (const auto& t : trace) {
    if (t.time_s > f.publish_time_s + 0.1 + 1e-3) {
      ASSERT_EQ(t.commanded_n, glm::vec3(0.0f)) << t.time_s;
    }
  }
}

// A simulation stepping at 4 Hz (a 32^3 session on a loaded llvmpipe machine) publishes a force
// every 250 ms: its force reaches the hand the whole time, because the stale threshold is three
// of its periods (0.75 s) rather than stale_after (0.05 s here). When it then stalls, the force
// fades once older than stale_after_max (0.5 s here) + fade_time.
TEST(HapticLoop, SlowSimulationKeepsTheForceAndAStalledOneFades) {
  auto device = std::make_shared<HostDevice>(5.0f);
  device->pushPose(glm::vec3(0.0f));
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  HapticLoopSettings s = fadingSettings();
  s.pipeline.safety.stale_after_max_s = 0.9;
  HapticLoop loop(device, poses, forces, s);
  constexpr double kRateHz = 4.0;
  const auto publish = [&] {
    ForceFrame f;
    f.force_n = glm::vec3(0.0f, 0.0f, -1.5f);
    f.publish_time_s = monotonicNowS();
    f.sim_rate_hz = kRateHz;
    forces.write(f);
    return f.publish_time_s;
  };
  publish();
  loop.start();
  ASSERT_TRUE(waitFor([&] { return loop.stats().ticks > 0; }, 10000ms));
  std::vector<TraceSample> trace;
  double last_publish_s = 0.0;
  for (int frame = 0; frame < 8; ++frame) {  // the slow simulation thread: a 250 ms step each
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(1000.0 / kRateHz)));
    last_publish_s = publish();
  }
  const double slow_end_s = last_publish_s;
  loop.drainTrace(trace);
  ASSERT_TRUE(waitFor([&] { return device->lastForce() == glm::vec3(0.0f); }, 10000ms));  // stalled
  // The force reaches zero at the end of the fade; keep the loop running a while so the trace
  // holds periods past it (drained at once, it may end before the first of them).
  std::this_thread::sleep_for(100ms);
  loop.drainTrace(trace);
  const double stale_after = loop.latest().stale_after_s;
  loop.stop();
  EXPECT_DOUBLE_EQ(stale_after, 0.75);  // 3 periods of 4 Hz, within [0.05, 0.9] s
  ASSERT_FALSE(trace.empty());
  std::size_t slow = 0, faded = 0;
  for (const auto& t : trace) {
    if (t.time_s > trace.front().time_s + 0.1 && t.time_s <= slow_end_s) {  // between the slow frames
      ++slow;
      ASSERT_NEAR(t.commanded_n.z, -1.5f, 1e-5f) << "the slow simulation's force reaches the hand at " << t.time_s;
    }
    if (t.time_s > slow_end_s + stale_after + 0.05 + 1e-3) {  // past threshold + fade after the stall
      ++faded;
      ASSERT_EQ(t.commanded_n, glm::vec3(0.0f)) << t.time_s;
    }
  }
  EXPECT_GT(slow, 100u);
  EXPECT_GT(faded, 0u);
}

// stop() slews the command down to zero at the slew rate before the thread ends (no 1.5 N to 0
// step in the hand), and the last command is zero.
TEST(HapticLoop, StopSlewsTheForceDownToZero) {
  auto device = std::make_shared<FaultyDevice>(1 << 30);  // never fails; records every force
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  ForceFrame f;
  f.force_n = glm::vec3(1.5f, 0.0f, 0.0f);
  f.publish_time_s = 1e300;  // never stale
  forces.write(f);
  HapticLoopSettings s = loopSettings();
  s.pipeline.safety.slew_rate_n_s = 100.0f;  // 0.1 N per period: 15 periods from 1.5 N to 0
  HapticLoop loop(device, poses, forces, s);
  loop.start();
  ASSERT_TRUE(waitFor([&] { return glm::length(loop.latest().commanded_n) > 1.49f; }, 10000ms));
  loop.stop();
  const auto seen = device->forces();
  ASSERT_GE(seen.size(), 20u);
  EXPECT_EQ(seen.back(), glm::vec3(0.0f));
  // Each period's step is at most slew * (two nominal periods, the loop's cap on dt).
  const float max_step = 100.0f * 2e-3f * (1.0f + 1e-5f);
  std::size_t peak = 0;
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_LE(glm::length(seen[i] - seen[i - 1]), max_step) << "command " << i << " of " << seen.size();
    if (glm::length(seen[i]) > 1.49f) peak = i;
  }
  EXPECT_GE(seen.size() - peak, 8u);  // the way down took several periods
}

// A slow slew (4 N at 8 N/s: 0.5 s) is wound down the whole way at the slew rate; stop() used
// to give up after 0.25 s and drop the remaining 2 N at once. The trace keeps the way down.
TEST(HapticLoop, StopWindsDownAtTheSlewRateAllTheWay) {
  auto device = std::make_shared<FaultyDevice>(1 << 30);  // never fails; records every force
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  ForceFrame f;
  f.force_n = glm::vec3(0.0f, 4.0f, 0.0f);
  f.publish_time_s = 1e300;  // never stale
  forces.write(f);
  HapticLoopSettings s = loopSettings();
  s.pipeline.safety.max_force_n = 4.0f;
  s.pipeline.safety.slew_rate_n_s = 8.0f;
  HapticLoop loop(device, poses, forces, s);
  loop.start();
  ASSERT_TRUE(waitFor([&] { return glm::length(loop.latest().commanded_n) > 3.99f; }, 20000ms));
  loop.stop();
  const auto seen = device->forces();
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), glm::vec3(0.0f));
  const float max_step = 8.0f * 2e-3f * (1.0f + 1e-5f);  // slew * the loop's cap on dt
  for (std::size_t i = 1; i < seen.size(); ++i) {
    ASSERT_LE(glm::length(seen[i] - seen[i - 1]), max_step) << "command " << i << " of " << seen.size();
  }
  std::vector<TraceSample> trace;
  loop.drainTrace(trace);
  ASSERT_FALSE(trace.empty());
  EXPECT_EQ(trace.back().commanded_n, glm::vec3(0.0f));  // the last traced period is the zero
  std::size_t peak = 0;
  for (std::size_t i = 0; i < trace.size(); ++i) {
    if (glm::length(trace[i].commanded_n) > 3.99f) peak = i;
  }
  EXPECT_GE(trace.size() - peak, 250u);  // 4 N at <= 16 mN per period: at least 250 periods down
}

TEST(HapticLoop, RefusesASlewTooSlowToWindDownOnStop) {
  HapticLoopSettings s = loopSettings();
  s.pipeline.safety.max_force_n = 4.0f;
  s.pipeline.safety.slew_rate_n_s = 4.0f / static_cast<float>(kMaxWindDownS) * 0.99f;
  try {
    s.validate();
    ADD_FAILURE() << "a slew rate needing more than kMaxWindDownS to stop was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("slew_rate"), std::string::npos) << e.what();
  }
  s.pipeline.safety.slew_rate_n_s = 4.0f / static_cast<float>(kMaxWindDownS);
  EXPECT_NO_THROW(s.validate());
}

// Two loops on one device would each command force past the other's safety stage; the second
// start() must fail, and the device must be free again once the first has stopped.
TEST(HapticLoop, OneLoopPerDevice) {
  auto device = std::make_shared<NullDevice>(5.0f);
  Mailbox<PoseFrame> poses1, poses2;
  Mailbox<ForceFrame> forces;
  HapticLoop first(device, poses1, forces, loopSettings());
  HapticLoop second(device, poses2, forces, loopSettings());
  first.start();
  try {
    second.start();
    ADD_FAILURE() << "a second loop started on a device already driven";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is in use"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(second.running());
  EXPECT_THROW(DeviceClaim(*device, "write_force() to it"), Error);  // a host call is refused too
  ASSERT_TRUE(waitFor([&] { return first.stats().ticks > 3; }, 10000ms));
  first.stop();
  EXPECT_FALSE(device->claimed());
  second.start();  // the device is free again
  EXPECT_TRUE(device->claimed());
  second.stop();
  EXPECT_FALSE(device->claimed());
}

// Several host threads stop a loop at once (Python threads, atexit): one joins, the others wait
// for it; none throws or hangs (two concurrent joins of one thread hang or crash).
TEST(HapticLoop, StopFromManyThreadsAtOnce) {
  auto device = std::make_shared<NullDevice>(5.0f);
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  for (int round = 0; round < 5; ++round) {
    HapticLoop loop(device, poses, forces, loopSettings());
    loop.start();
    ASSERT_TRUE(waitFor([&] { return loop.stats().ticks > 3; }, 10000ms));
    std::atomic<int> errors{0};
    std::vector<std::thread> stoppers;
    for (int i = 0; i < 4; ++i) {
      stoppers.emplace_back([&] {
        try {
          loop.stop();
        } catch (...) {
          ++errors;
        }
      });
    }
    for (auto& t : stoppers) t.join();
    EXPECT_EQ(errors.load(), 0);
    EXPECT_FALSE(loop.running());
  }
}

// The Falcon sends a force with its next read(); the zero on stop must not wait for a read that
// never comes, or the Falcon keeps pushing with the last force after the session ended.
TEST(HapticLoop, StopLeavesTheFalconWithZeroForce) {
  auto sim = std::make_shared<falcon::SimulatedFalconTransport>(falcon::SimulatedFalconOptions{});
  falcon::FalconOptions options;
  options.homingTimeout_s = 5.0;
  auto device = falcon::openSimulatedFalcon(sim, options);
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  ForceFrame f;
  f.force_n = glm::vec3(0.0f, 0.0f, 1.5f);
  f.publish_time_s = 1e300;  // never stale
  forces.write(f);
  HapticLoop loop(device, poses, forces, loopSettings());
  loop.start();
  ASSERT_TRUE(waitFor([&] { return glm::length(sim->state().motorForce_n) > 1.0; }, 10000ms));
  loop.stop();  // no pause first: the loop was commanding 1.5 N up to its last period
  EXPECT_FALSE(loop.failed()) << loop.error();
  EXPECT_EQ(sim->state().lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));
  EXPECT_LT(glm::length(sim->state().motorForce_n), 1e-9);
}

TEST(HapticLoop, RejectsBadSettings) {
  Mailbox<PoseFrame> poses;
  Mailbox<ForceFrame> forces;
  HapticLoopSettings s = loopSettings();
  s.rate_hz = 50.0;
  EXPECT_THROW(HapticLoop(std::make_shared<NullDevice>(), poses, forces, s), InvalidArgument);
  EXPECT_THROW(HapticLoop(nullptr, poses, forces, loopSettings()), InvalidArgument);
  s = loopSettings();
  s.pipeline.safety.max_force_n = 11.0f;  // above the null device's 10 N
  EXPECT_THROW(HapticLoop(std::make_shared<NullDevice>(10.0f), poses, forces, s), InvalidArgument);
}

}  // namespace
}  // namespace hf::haptics
