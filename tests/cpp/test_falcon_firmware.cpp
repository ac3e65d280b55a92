// SPDX-License-Identifier: GPL-3.0-or-later
// Firmware upload through the simulated Falcon's bootloader, and the firmware file checks.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "haptics/falcon/firmware_loader.h"
#include "haptics/falcon/simulated_falcon.h"

using namespace hf::haptics::falcon;

namespace {

// A synthetic image (not Novint's firmware): every byte value, in a fixed pseudo-random order.
std::vector<std::uint8_t> syntheticFirmware(std::size_t n) {
  std::vector<std::uint8_t> bytes(n);
  std::uint32_t x = 12345;
  for (auto& b : bytes) {
    x = x * 1103515245u + 12345u;
    b = static_cast<std::uint8_t>(x >> 16);
  }
  return bytes;
}

FirmwareLoaderOptions fastOptions() {
  FirmwareLoaderOptions o;
  o.handshakeTries = 3;
  o.uploadAttempts = 3;
  o.handshakeTimeout = std::chrono::milliseconds(20);
  o.echoTimeout = std::chrono::milliseconds(20);
  return o;
}

struct Rig {
  explicit Rig(SimulatedFalconOptions options) : sim(std::move(options)), serial(sim) { sim.open(); }
  SimulatedFalconTransport sim;
  FtdiSerial serial;
};

SimulatedFalconOptions withImage(const std::vector<std::uint8_t>& image) {
  SimulatedFalconOptions o;
  o.expectedFirmware = image;
  return o;
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "hf_falcon_" + std::to_string(::getpid()) + "_" + name;
}

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FalconFirmware, UploadsThroughTheBootloaderAndEndsInNormalMode) {
  const auto image = syntheticFirmware(8492);
  Rig rig(withImage(image));
  ASSERT_FALSE(rig.sim.state().firmwareRunning);
  FirmwareLoader loader(rig.serial, fastOptions());
  loader.upload(image);
  const SimulatedFalconState s = rig.sim.state();
  EXPECT_TRUE(s.firmwareRunning);
  EXPECT_EQ(s.handshakes, 1);
  EXPECT_EQ(s.firmwareBytes, image.size());
  EXPECT_EQ(s.baudDivisor, 0x0002);
  EXPECT_EQ(s.latency_ms, 1);
  EXPECT_EQ(loader.attemptsUsed(), 1);
}

TEST(FalconFirmware, OneBadEchoIsRetriedAndSucceeds) {
  const auto image = syntheticFirmware(1000);
  auto options = withImage(image);
  options.faults.corruptEchoAtByte = 300;
  options.faults.corruptEchoUploads = 1;
  Rig rig(options);
  FirmwareLoader loader(rig.serial, fastOptions());
  loader.upload(image);
  EXPECT_TRUE(rig.sim.state().firmwareRunning);
  EXPECT_EQ(loader.attemptsUsed(), 2);
  EXPECT_EQ(rig.sim.state().handshakes, 2);
}

TEST(FalconFirmware, PersistentEchoMismatchFailsNamingTheByte) {
  const auto image = syntheticFirmware(1000);
  auto options = withImage(image);
  options.faults.corruptEchoAtByte = 300;
  options.faults.corruptEchoUploads = 1000;
  Rig rig(options);
  FirmwareLoader loader(rig.serial, fastOptions());
  const std::string what = errorOf([&] { loader.upload(image); });
  EXPECT_NE(what.find("after 3 attempts"), std::string::npos) << what;
  EXPECT_NE(what.find("echo mismatch at byte 300"), std::string::npos) << what;
  EXPECT_FALSE(rig.sim.state().firmwareRunning);
}

TEST(FalconFirmware, StalledEchoTimesOut) {
  const auto image = syntheticFirmware(500);
  auto options = withImage(image);
  options.faults.stallEchoAtByte = 130;
  options.faults.stallEchoUploads = 1000;
  Rig rig(options);
  FirmwareLoader loader(rig.serial, fastOptions());
  const std::string what = errorOf([&] { loader.upload(image); });
  EXPECT_NE(what.find("timeout: the echo stopped at byte 130 of 500"), std::string::npos) << what;
}

TEST(FalconFirmware, SilentBootloaderFailsTheHandshake) {
  const auto image = syntheticFirmware(100);
  auto options = withImage(image);
  options.faults.silentBootloader = true;
  Rig rig(options);
  FirmwareLoader loader(rig.serial, fastOptions());
  const std::string what = errorOf([&] { loader.upload(image); });
  EXPECT_NE(what.find("did not answer the handshake in 3 tries"), std::string::npos) << what;
}

TEST(FalconFirmware, UnplugDuringUploadIsAnUnplugError) {
  const auto image = syntheticFirmware(800);
  auto options = withImage(image);
  options.faults.unplugAtFirmwareByte = 200;
  Rig rig(options);
  FirmwareLoader loader(rig.serial, fastOptions());
  EXPECT_THROW(loader.upload(image), UsbUnplugged);
  EXPECT_EQ(loader.attemptsUsed(), 1);  // no retry into a missing device
}

TEST(FalconFirmware, WrongImageEchoesButDoesNotRun) {
  const auto image = syntheticFirmware(600);
  Rig rig(withImage(image));
  auto wrong = image;
  wrong[17] ^= 1;
  FirmwareLoader loader(rig.serial, fastOptions());
  loader.upload(wrong);  // the bootloader echoes whatever it gets ...
  EXPECT_FALSE(rig.sim.state().firmwareRunning);  // ... but the DSP does not run it
}

TEST(FalconFirmware, RejectsEmptyAndOversizedImages) {
  Rig rig(withImage(syntheticFirmware(10)));
  FirmwareLoader loader(rig.serial, fastOptions());
  EXPECT_THROW(loader.upload({}), hf::InvalidArgument);
  EXPECT_THROW(loader.upload(std::vector<std::uint8_t>(kMaxFirmwareBytes + 1, 0)), hf::InvalidArgument);
  EXPECT_EQ(rig.sim.state().handshakes, 0);  // nothing was sent
}

TEST(FalconFirmware, FileChecks) {
  const std::string good = tempPath("good.bin");
  const auto image = syntheticFirmware(7324);
  {
    std::ofstream out(good, std::ios::binary);
    out.write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
  }
  EXPECT_EQ(readFirmwareFile(good), image);

  const std::string missing = tempPath("missing.bin");
  std::string what = errorOf([&] { readFirmwareFile(missing); });
  EXPECT_NE(what.find("cannot be found"), std::string::npos) << what;
  EXPECT_THROW(readFirmwareFile(missing), hf::InvalidArgument);

  const std::string empty = tempPath("empty.bin");
  { std::ofstream out(empty, std::ios::binary); }
  what = errorOf([&] { readFirmwareFile(empty); });
  EXPECT_NE(what.find("is empty"), std::string::npos) << what;

  const std::string big = tempPath("big.bin");
  {
    std::ofstream out(big, std::ios::binary);
    const std::vector<char> zeros(kMaxFirmwareBytes + 1, 0);
    out.write(zeros.data(), static_cast<std::streamsize>(zeros.size()));
  }
  what = errorOf([&] { readFirmwareFile(big); });
  EXPECT_NE(what.find("more than 65536"), std::string::npos) << what;

  what = errorOf([&] { readFirmwareFile(::testing::TempDir()); });
  EXPECT_NE(what.find("not a regular file"), std::string::npos) << what;
  EXPECT_THROW(readFirmwareFile(""), hf::InvalidArgument);

  if (::geteuid() != 0) {  // root reads anything
    const std::string locked = tempPath("locked.bin");
    { std::ofstream out(locked, std::ios::binary); out << "x"; }
    ::chmod(locked.c_str(), 0);
    what = errorOf([&] { readFirmwareFile(locked); });
    EXPECT_NE(what.find("cannot be read"), std::string::npos) << what;
    std::remove(locked.c_str());
  }
  for (const auto& p : {good, empty, big}) std::remove(p.c_str());
}
