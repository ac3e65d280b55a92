// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The Novint Falcon as a haptics Device: composes the transport (USB or simulated), FtdiSerial,
// the firmware loader, the packet codec and the kinematics.
//
// Construction opens it: FTDI setup -> normal mode -> firmware check (first well-formed reply)
// -> upload from options.firmware if not loaded -> homing (red LED, homing bit) until all three
// axes report homed (green LED), when options.home. Every read() is one packet exchange: it
// sends the latest command (the force from writeForce(), zero until homed; the homing bit and
// the LEDs) and decodes the reply. So a force takes effect at the next read(), one period later.
// Unplugged: read() throws hf::Error, writeForce() does nothing, close() does not throw.
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>

#include "haptics/devices/device.h"
#include "haptics/falcon/falcon_kinematics.h"
#include "haptics/falcon/falcon_packet.h"
#include "haptics/falcon/firmware_loader.h"

namespace hf::haptics::falcon {

constexpr float kFalconPeakForce_n = 8.9f;  // Novint's specification

struct FalconOptions {
  std::vector<std::uint8_t> firmware;   // uploaded when the firmware is not running; empty: none
  bool home = true;                     // the constructor waits until the user has homed it
  double homingTimeout_s = 60.0;        // then gives up with instructions
  float maxForce_n = 8.0f;              // never exceeded (CHAI3D's Falcon profile)
  double velocityFilter_s = 0.015;      // time constant of the velocity low-pass (s)
  std::chrono::milliseconds replyTimeout{5};   // per read() (a reply takes ~1-2 ms at 1 ms latency)
  std::chrono::milliseconds probeTimeout{50};  // per packet of the firmware probe at open
  int maxMissedReplies = 50;            // consecutive; then read() throws (link lost)
  int firmwareProbePackets = 5;         // exchanges tried when checking for running firmware
  FirmwareLoaderOptions loader;
  std::function<double()> clock;        // seconds; empty: monotonicNowS()
  DeviceInfo info;                      // name/kind/serial/limits reported by info()
};

// The Falcon's DeviceInfo: +-0.04 m workspace, 8 N, 3000 N/m, 20 N s/m.
DeviceInfo falconInfo(const std::string& name, const std::string& kind, const std::string& serial);

struct FalconStats {
  long packets = 0;            // replies decoded
  long missedReplies = 0;      // exchanges without a reply
  long forceClamps = 0;        // writeForce() magnitudes above maxForce_n
  long commandClamps = 0;      // torques that did not fit int16 (scaled down together)
  long forwardFailures = 0;    // homed readings where forward kinematics did not converge
  int uploadAttempts = 0;      // 0: the firmware was already running
  bool firmwareUploaded = false;
};

// Exchanges up to `packets` zero-force packets; true at the first well-formed reply.
bool firmwareRunning(FtdiSerial& serial, int packets, std::chrono::milliseconds timeout);

// Opens serial's transport, sets up the FTDI (reset, 8N1, no flow control, normal mode) and
// returns firmwareRunning(serial, packets, timeout).
bool openAndProbeFirmware(FtdiSerial& serial, int packets, std::chrono::milliseconds timeout);

class FalconDevice : public Device {
 public:
  FalconDevice(std::shared_ptr<UsbTransport> usb, FalconOptions options);
  ~FalconDevice() override;
  FalconDevice(const FalconDevice&) = delete;
  FalconDevice& operator=(const FalconDevice&) = delete;

  DeviceInfo info() const override;
  DeviceState read() override;
  void writeForce(const glm::vec3& force_n) override;
  // Zero motor command sent in one packet exchange now, not with the next read().
  void zeroForce() noexcept override;
  void close() override;

  FalconStats stats() const;
  // Exchanges packets until homed or the timeout; throws hf::Error with instructions on timeout.
  void home(double timeout_s);

 private:
  // One packet out, the newest reply in; nullopt if none came within the timeout.
  std::optional<FalconReport> exchange();
  void update(const FalconReport& report);
  double now() const;
  [[noreturn]] void lost(const std::exception& e);
  [[noreturn]] void throwDead() const;  // UsbUnplugged when it was unplugged, else Error

  std::shared_ptr<UsbTransport> usb_;
  FalconOptions opt_;
  FtdiSerial serial_;
  FalconKinematics kin_;
  FrameScanner replies_;
  mutable std::mutex mu_;
  FalconCommand command_;       // motor part: the last writeForce(), applied once homed
  DeviceState state_;
  FalconStats stats_;
  bool haveReading_ = false;
  bool closed_ = false;
  bool dead_ = false;
  std::string deadReason_;
  bool deadUnplugged_ = false;
  int missedInRow_ = 0;
};

}  // namespace hf::haptics::falcon
