// SPDX-License-Identifier: GPL-3.0-or-later
// The whole Falcon driver (FTDI setup, firmware upload, homing, packets, kinematics) against the
// simulated Falcon, and the libusb enumeration path on this machine.
#include <gtest/gtest.h>

#include <cmath>

#include "haptics/falcon/falcon.h"
#include "haptics/falcon/libusb_transport.h"

using namespace hf::haptics::falcon;
using hf::haptics::DeviceState;

namespace {

std::vector<std::uint8_t> syntheticFirmware(std::size_t n) {
  std::vector<std::uint8_t> bytes(n);
  for (std::size_t i = 0; i < n; ++i) bytes[i] = static_cast<std::uint8_t>((i * 37u + 11u) ^ (i >> 3));
  return bytes;
}

FalconOptions fastOptions() {
  FalconOptions o;
  o.homingTimeout_s = 5.0;
  o.probeTimeout = std::chrono::milliseconds(20);
  o.loader.handshakeTries = 3;
  o.loader.uploadAttempts = 3;
  o.loader.handshakeTimeout = std::chrono::milliseconds(20);
  o.loader.echoTimeout = std::chrono::milliseconds(20);
  return o;
}

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Reads n times, writing `force` after each read, as a haptic loop does.
DeviceState run(FalconDevice& device, int n, const glm::vec3& force) {
  DeviceState s;
  for (int i = 0; i < n; ++i) {
    s = device.read();
    device.writeForce(force);
  }
  return s;
}

}  // namespace

TEST(FalconDevice, OpensWithUploadAndHomingOnTheSimulatedFalcon) {
  SimulatedFalconOptions sim_options;
  sim_options.expectedFirmware = syntheticFirmware(8492);
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.firmware = sim_options.expectedFirmware;
  auto device = openSimulatedFalcon(sim, options);
  const SimulatedFalconState s = sim->state();
  EXPECT_TRUE(s.firmwareRunning);
  EXPECT_EQ(s.homed, 0x7);
  EXPECT_EQ(device->stats().uploadAttempts, 1);
  EXPECT_TRUE(device->stats().firmwareUploaded);
  // Homing took the gesture's pull-out (about 0.2 s of simulated packets), red LED throughout.
  EXPECT_GT(s.packets, 100);
  EXPECT_EQ(s.leds, led::kRed);
  EXPECT_TRUE(s.homingMode);
  const DeviceState state = device->read();
  EXPECT_TRUE(state.homed);
  EXPECT_EQ(sim->state().leds, led::kGreen);
  EXPECT_FALSE(sim->state().homingMode);
  EXPECT_EQ(device->info().kind, "simulated_falcon");
  EXPECT_FLOAT_EQ(device->info().max_force_n, 8.0f);
}

TEST(FalconDevice, PositionFollowsTheGripAfterHoming) {
  SimulatedFalconOptions sim_options;
  // Homing gesture, then the hand moves along x at 0.05 m/s from t = 1 s.
  sim_options.handPath = [](double t) {
    return t < 1.0 ? homingGesture(t) : glm::dvec3(std::min(0.05 * (t - 1.0), 0.03), 0.0, 0.0);
  };
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.clock = simulatedClock(sim);  // readings stamped with simulated time: exact velocities
  auto device = openSimulatedFalcon(sim, options);
  run(*device, 1200 - static_cast<int>(sim->state().packets), glm::vec3(0.0f));  // to t = 1.2 s
  const DeviceState s = device->read();
  const SimulatedFalconState truth = sim->state();
  EXPECT_NEAR(s.position_m.x, truth.position_m.x, 3e-4);
  EXPECT_NEAR(s.position_m.y, truth.position_m.y, 3e-4);
  EXPECT_NEAR(s.position_m.z, truth.position_m.z, 3e-4);
  EXPECT_GT(truth.position_m.x, 0.005);  // it did move
  // Velocity by filtered differencing of the quantised positions: about 0.05 m/s.
  EXPECT_NEAR(s.velocity_m_s.x, 0.05, 0.01);
  EXPECT_NEAR(s.velocity_m_s.z, 0.0, 0.01);
  EXPECT_NEAR(s.time_s, truth.time_s, 1e-9);
  // Independent of load: the simulated Falcon's reply is queued by the time read() looks, and
  // FtdiSerial::read looks at least once even if this thread was preempted past its deadline
  // (it used to count a missed reply then, under load average > 5).
  EXPECT_EQ(device->stats().forwardFailures, 0);
  EXPECT_EQ(device->stats().missedReplies, 0);
}

TEST(FalconDevice, ForceReachesTheGripThroughTheWholeStack) {
  auto sim = std::make_shared<SimulatedFalconTransport>(SimulatedFalconOptions{});
  auto device = openSimulatedFalcon(sim, fastOptions());
  // The hand holds the grip at the centre with 300 N/m: 2 N along z moves it 2/300 m.
  const DeviceState s = run(*device, 1500, glm::vec3(0.0f, 0.0f, 2.0f));
  const SimulatedFalconState truth = sim->state();
  EXPECT_NEAR(truth.motorForce_n.z, 2.0, 0.02);
  EXPECT_NEAR(truth.motorForce_n.x, 0.0, 0.02);
  EXPECT_NEAR(truth.motorForce_n.y, 0.0, 0.02);
  EXPECT_NEAR(truth.position_m.z, 2.0 / 300.0, 2e-4);
  EXPECT_NEAR(s.position_m.z, 2.0 / 300.0, 4e-4);
  EXPECT_EQ(device->stats().forceClamps, 0);
  EXPECT_EQ(device->stats().commandClamps, 0);
}

TEST(FalconDevice, NeverExceedsTheMaximumForce) {
  auto sim = std::make_shared<SimulatedFalconTransport>(SimulatedFalconOptions{});
  auto device = openSimulatedFalcon(sim, fastOptions());
  run(*device, 20, glm::vec3(30.0f, 0.0f, -40.0f));  // 50 N asked
  const SimulatedFalconState truth = sim->state();
  EXPECT_NEAR(glm::length(truth.motorForce_n), 8.0, 0.1);
  EXPECT_NEAR(truth.motorForce_n.x / truth.motorForce_n.z, -0.75, 0.01);  // direction kept
  EXPECT_EQ(device->stats().forceClamps, 20);
  EXPECT_THROW(device->writeForce(glm::vec3(NAN, 0.0f, 0.0f)), hf::InvalidArgument);
}

TEST(FalconDevice, NoForceBeforeHoming) {
  SimulatedFalconOptions sim_options;
  sim_options.handPath = [](double) { return glm::dvec3(0.0); };  // the user never homes it
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.home = false;
  auto device = openSimulatedFalcon(sim, options);
  const DeviceState s = run(*device, 50, glm::vec3(0.0f, 0.0f, 5.0f));
  EXPECT_FALSE(s.homed);
  const SimulatedFalconState truth = sim->state();
  EXPECT_EQ(truth.lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));
  EXPECT_TRUE(truth.lastCommand.homing);
  EXPECT_EQ(truth.leds, led::kRed);
  EXPECT_DOUBLE_EQ(glm::length(truth.motorForce_n), 0.0);
}

TEST(FalconDevice, HomingTimesOutWithInstructions) {
  SimulatedFalconOptions sim_options;
  sim_options.handPath = [](double) { return glm::dvec3(0.0); };
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.homingTimeout_s = 0.2;
  const std::string what = errorOf([&] { openSimulatedFalcon(sim, options); });
  EXPECT_NE(what.find("not homed after 0.2 s"), std::string::npos) << what;
  EXPECT_NE(what.find("pull the grip all the way out"), std::string::npos) << what;
  EXPECT_FALSE(sim->isOpen());  // released
}

TEST(FalconDevice, MissingFirmwareSaysWhatToPass) {
  SimulatedFalconOptions sim_options;
  sim_options.expectedFirmware = syntheticFirmware(300);
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  const std::string what = errorOf([&] { openSimulatedFalcon(sim, fastOptions()); });
  EXPECT_NE(what.find("firmware is not loaded"), std::string::npos) << what;
  EXPECT_NE(what.find("firmware='nvent_firmware.bin'"), std::string::npos) << what;
}

TEST(FalconDevice, WrongFirmwareIsReported) {
  SimulatedFalconOptions sim_options;
  sim_options.expectedFirmware = syntheticFirmware(300);
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.firmware = syntheticFirmware(299);
  const std::string what = errorOf([&] { openSimulatedFalcon(sim, options); });
  EXPECT_NE(what.find("does not answer packets"), std::string::npos) << what;
}

TEST(FalconDevice, ButtonsAreReported) {
  SimulatedFalconOptions sim_options;
  sim_options.buttons = [](double t) { return t > 1.0 ? button::kCentre | button::kLeft : 0u; };
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  auto device = openSimulatedFalcon(sim, fastOptions());
  EXPECT_EQ(device->read().buttons, 0u);
  const DeviceState s = run(*device, 1100, glm::vec3(0.0f));
  EXPECT_EQ(s.buttons, button::kCentre | button::kLeft);
}

TEST(FalconDevice, UnplugMidSessionStopsEverythingCleanly) {
  SimulatedFalconOptions sim_options;
  sim_options.faults.unplugAtPacket = 700;  // after homing (~200 packets)
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  auto device = openSimulatedFalcon(sim, fastOptions());
  std::string what;
  int reads = 0;
  try {
    for (; reads < 2000; ++reads) {
      device->read();
      device->writeForce(glm::vec3(1.0f, 0.0f, 0.0f));
    }
  } catch (const hf::Error& e) {
    what = e.what();
  }
  EXPECT_LT(reads, 700);
  EXPECT_NE(what.find("was unplugged"), std::string::npos) << what;
  EXPECT_NE(what.find("Forces are off"), std::string::npos) << what;
  EXPECT_THROW(device->read(), hf::Error);  // stays gone
  EXPECT_NO_THROW(device->writeForce(glm::vec3(1.0f)));
  EXPECT_NO_THROW(device->close());
  EXPECT_NO_THROW(device->close());
  EXPECT_FALSE(sim->isOpen());
}

TEST(FalconDevice, MissedRepliesAreToleratedThenTheLinkIsLost) {
  SimulatedFalconOptions sim_options;
  sim_options.faults.dropRepliesFrom = 400;
  sim_options.faults.dropRepliesCount = 5;
  auto sim = std::make_shared<SimulatedFalconTransport>(sim_options);
  FalconOptions options = fastOptions();
  options.replyTimeout = std::chrono::milliseconds(2);
  options.maxMissedReplies = 10;
  auto device = openSimulatedFalcon(sim, options);
  EXPECT_NO_THROW(run(*device, 400, glm::vec3(0.0f)));
  EXPECT_EQ(device->stats().missedReplies, 5);

  SimulatedFalconOptions silent = sim_options;
  silent.faults.dropRepliesFrom = 400;
  silent.faults.dropRepliesCount = 1000000;
  auto sim2 = std::make_shared<SimulatedFalconTransport>(silent);
  auto device2 = openSimulatedFalcon(sim2, options);
  const std::string what = errorOf([&] { run(*device2, 400, glm::vec3(0.0f)); });
  EXPECT_NE(what.find("no reply to 10 packets in a row"), std::string::npos) << what;
  EXPECT_EQ(sim2->state().lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));  // zero sent on the way out
}

// A force set by writeForce() goes out with the next read(); the zero a haptic loop commands
// when it stops must go out at once, or the Falcon keeps pushing with the last force.
TEST(FalconDevice, ZeroForceIsSentAtOnce) {
  auto sim = std::make_shared<SimulatedFalconTransport>(SimulatedFalconOptions{});
  auto device = openSimulatedFalcon(sim, fastOptions());
  run(*device, 10, glm::vec3(0.0f, 3.0f, 0.0f));
  device->read();
  EXPECT_GT(glm::length(sim->state().motorForce_n), 2.5);
  device->writeForce(glm::vec3(0.0f));  // alone: still on the Falcon until the next read()
  EXPECT_NE(sim->state().lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));
  device->zeroForce();
  EXPECT_EQ(sim->state().lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));
  EXPECT_LT(glm::length(sim->state().motorForce_n), 1e-9);
  EXPECT_TRUE(sim->isOpen());  // the device stays usable
  EXPECT_NO_THROW(device->read());
  device->close();
  EXPECT_NO_THROW(device->zeroForce());  // closed: nothing to send, never throws
}

TEST(FalconDevice, CloseSendsZeroForceAndIsIdempotent) {
  auto sim = std::make_shared<SimulatedFalconTransport>(SimulatedFalconOptions{});
  auto device = openSimulatedFalcon(sim, fastOptions());
  run(*device, 10, glm::vec3(0.0f, 3.0f, 0.0f));
  device->read();  // the last force goes out
  EXPECT_GT(glm::length(sim->state().motorForce_n), 2.5);
  device->close();
  EXPECT_EQ(sim->state().lastCommand.motor, (std::array<std::int16_t, 3>{0, 0, 0}));
  EXPECT_FALSE(sim->isOpen());
  EXPECT_NO_THROW(device->close());
  EXPECT_THROW(device->read(), hf::Error);
  EXPECT_NO_THROW(device->writeForce(glm::vec3(1.0f)));
}

TEST(FalconDevice, RejectsBadOptions) {
  auto sim = std::make_shared<SimulatedFalconTransport>(SimulatedFalconOptions{});
  FalconOptions options = fastOptions();
  options.maxForce_n = -1.0f;
  EXPECT_THROW(openSimulatedFalcon(sim, options), hf::InvalidArgument);
  EXPECT_THROW(openSimulatedFalcon(nullptr, fastOptions()), hf::InvalidArgument);
  SimulatedFalconOptions bad;
  bad.handMass_kg = 0.0;
  EXPECT_THROW(SimulatedFalconTransport{bad}, hf::InvalidArgument);
}

// No Falcon is plugged in here: enumeration through libusb answers with an empty list, opening
// says so clearly, and a transport for a missing bus/address reports it as unplugged.
TEST(FalconEnumeration, ListsWhatIsPluggedInThroughLibusb) {
  const std::vector<FalconListing> found = listFalcons(true);
  for (const FalconListing& f : found) {
    EXPECT_GT(f.bus, 0);
    EXPECT_GT(f.address, 0);
    if (!f.permissionOk) {
      EXPECT_NE(f.problem.find("udev"), std::string::npos);
    }
  }
  if (found.empty()) {
    const std::string what = errorOf([] { openFalcon(0, FalconOptions{}); });
    EXPECT_NE(what.find("no Novint Falcon (USB 0403:cb48) is plugged in"), std::string::npos) << what;
  } else {
    EXPECT_THROW(openFalcon(static_cast<int>(found.size()), FalconOptions{}), hf::InvalidArgument);
  }
  LibusbTransport nowhere(255, 255);
  EXPECT_THROW(nowhere.open(), UsbUnplugged);
  EXPECT_FALSE(nowhere.isOpen());
  EXPECT_NO_THROW(nowhere.close());
  EXPECT_NE(udevRule().find("ATTRS{idProduct}==\"cb48\""), std::string::npos);
}
