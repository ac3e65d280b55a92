// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/falcon_device.h"

#include <cmath>

#include "common/finite.h"
#include "common/format.h"
#include "haptics/handoff/clock.h"

namespace hf::haptics::falcon {
namespace {

UsbTransport& checked(const std::shared_ptr<UsbTransport>& usb) {
  if (!usb) throw InvalidArgument("FalconDevice needs a USB transport, got none");
  return *usb;
}

}  // namespace

DeviceInfo falconInfo(const std::string& name, const std::string& kind, const std::string& serial) {
  DeviceInfo info;
  info.name = name;
  info.kind = kind;
  info.serial = serial;
  info.workspace_min_m = glm::vec3(static_cast<float>(-kWorkspaceHalfEdge));
  info.workspace_max_m = glm::vec3(static_cast<float>(kWorkspaceHalfEdge));
  // Rendering limits as CHAI3D's Falcon device specification states them (CFalconDevice: max
  // linear force 8 N, max linear stiffness 3000 N/m, max linear damping 20 N s/m): the default
  // force gain and the passivity controller's damper are bounded by them.
  info.max_force_n = 8.0f;
  info.max_stiffness_n_m = 3000.0f;
  info.max_damping_n_s_m = 20.0f;
  // One count of every encoder, the worst place in the cube (about 0.1 mm).
  info.position_resolution_m = static_cast<float>(FalconKinematics().positionResolutionM());
  return info;
}

bool firmwareRunning(FtdiSerial& serial, int packets, std::chrono::milliseconds timeout) {
  FrameScanner scanner;
  const Frame zero = encodeCommand(FalconCommand{});
  for (int i = 0; i < packets; ++i) {
    serial.write(zero.data(), zero.size());
    std::uint8_t buf[kFrameBytes];
    const std::size_t n = serial.read(buf, sizeof buf, timeout);
    scanner.push(buf, n);
    if (scanner.pop()) {
      serial.purge(true, false);  // later replies to the probe are not readings
      return true;
    }
  }
  return false;
}

bool openAndProbeFirmware(FtdiSerial& serial, int packets, std::chrono::milliseconds timeout) {
  serial.transport().open();
  serial.reset();
  serial.setLine8N1();
  serial.setNoFlowControl();
  enterNormalMode(serial);
  return firmwareRunning(serial, packets, timeout);
}

FalconDevice::FalconDevice(std::shared_ptr<UsbTransport> usb, FalconOptions options)
    : usb_(std::move(usb)), opt_(std::move(options)), serial_(checked(usb_)) {
  if (!(std::isfinite(opt_.maxForce_n) && opt_.maxForce_n > 0.0f && opt_.maxForce_n <= kFalconPeakForce_n))
    throw InvalidArgument("Falcon max force must be in (0, " + num(kFalconPeakForce_n) +
                          "] N (the Falcon's peak force), got " + num(opt_.maxForce_n));
  if (!(opt_.velocityFilter_s >= 0.0 && opt_.velocityFilter_s <= 1.0))
    throw InvalidArgument("Falcon velocity filter time constant must be in [0, 1] s, got " + num(opt_.velocityFilter_s));
  if (!(opt_.homingTimeout_s > 0.0 && opt_.homingTimeout_s <= 3600.0))
    throw InvalidArgument("Falcon homing timeout must be in (0, 3600] s, got " + num(opt_.homingTimeout_s));
  if (opt_.replyTimeout.count() < 1 || opt_.probeTimeout.count() < 1 || opt_.maxMissedReplies < 1 ||
      opt_.firmwareProbePackets < 1)
    throw InvalidArgument("Falcon reply/probe timeouts (ms), missed-reply limit and probe packets must be at least 1");
  if (opt_.info.name.empty()) opt_.info = falconInfo("Novint Falcon", "falcon", "");
  if (opt_.info.max_force_n <= 0.0f || opt_.info.max_force_n > opt_.maxForce_n) opt_.info.max_force_n = opt_.maxForce_n;
  const std::string who = usb_->describe();
  try {
    if (!openAndProbeFirmware(serial_, opt_.firmwareProbePackets, opt_.probeTimeout)) {
      if (opt_.firmware.empty())
        throw Error(who + ": the Falcon's firmware is not loaded (it is lost at every power-off). Pass the "
                    "firmware file from Novint's driver or SDK, e.g. open_falcon(firmware='nvent_firmware.bin')");
      FirmwareLoader loader(serial_, opt_.loader);
      try {
        loader.upload(opt_.firmware);
      } catch (...) {
        stats_.uploadAttempts = loader.attemptsUsed();
        throw;
      }
      stats_.uploadAttempts = loader.attemptsUsed();
      stats_.firmwareUploaded = true;
      if (!firmwareRunning(serial_, opt_.firmwareProbePackets, opt_.probeTimeout))
        throw Error(who + ": the firmware was uploaded and every byte echoed, but the Falcon does not answer "
                    "packets: is the file the Falcon's firmware (nvent_firmware.bin)? Power-cycle the Falcon and retry");
    }
    if (opt_.home) home(opt_.homingTimeout_s);
  } catch (...) {
    usb_->close();
    throw;
  }
}

FalconDevice::~FalconDevice() { close(); }

DeviceInfo FalconDevice::info() const { return opt_.info; }

FalconStats FalconDevice::stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  return stats_;
}

double FalconDevice::now() const { return opt_.clock ? opt_.clock() : monotonicNowS(); }

std::optional<FalconReport> FalconDevice::exchange() {
  FalconCommand command = command_;
  if (state_.homed) {
    command.homing = false;
    command.leds = led::kGreen;
  } else {
    command.motor = {0, 0, 0};  // no force before homing: the encoders are not zeroed yet
    command.homing = true;
    command.leds = led::kRed;
  }
  const Frame frame = encodeCommand(command);
  serial_.write(frame.data(), frame.size());
  std::uint8_t buf[4 * kFrameBytes];
  std::size_t n = serial_.read(buf, kFrameBytes, opt_.replyTimeout);
  replies_.push(buf, n);
  // Late replies that came in the same transfers: keep only the newest reading.
  while ((n = serial_.readBuffered(buf, sizeof buf)) > 0) replies_.push(buf, n);
  std::optional<FalconReport> newest;
  while (const auto f = replies_.pop())
    if (const auto report = decodeReport(f->data(), f->size())) newest = report;
  if (newest) {
    ++stats_.packets;
    missedInRow_ = 0;
  } else {
    ++stats_.missedReplies;
    if (++missedInRow_ >= opt_.maxMissedReplies)
      throw Error("no reply to " + std::to_string(missedInRow_) + " packets in a row (" +
                  std::to_string(opt_.replyTimeout.count()) + " ms each): the link is lost; check the USB cable "
                  "and the Falcon's power");
  }
  return newest;
}

void FalconDevice::update(const FalconReport& report) {
  const double t = now();
  const bool homed = report.allHomed();
  if (homed && !state_.homed) haveReading_ = false;  // homing re-zeroes the encoders: position jumps
  const glm::dvec3 previous(state_.position_m);
  const ForwardResult fk = kin_.forward(FalconKinematics::anglesFromCounts(report.encoder),
                                        haveReading_ ? previous : glm::dvec3(0.0));
  glm::dvec3 p = fk.position_m;
  if (!fk.converged) {
    if (homed) ++stats_.forwardFailures;  // before homing the counts are arbitrary: expected
    if (haveReading_) p = previous;
  }
  glm::dvec3 v(0.0);
  if (haveReading_ && t > state_.time_s) {
    const double dt = t - state_.time_s;
    const glm::dvec3 raw = (p - previous) / dt;
    const double alpha = dt / (opt_.velocityFilter_s + dt);
    v = glm::dvec3(state_.velocity_m_s) + alpha * (raw - glm::dvec3(state_.velocity_m_s));
  } else if (haveReading_) {
    v = state_.velocity_m_s;
  }
  state_.position_m = glm::vec3(p);
  state_.velocity_m_s = glm::vec3(v);
  state_.buttons = report.buttons;
  state_.homed = homed;
  state_.time_s = t;
  haveReading_ = true;
}

void FalconDevice::throwDead() const {
  if (deadUnplugged_) throw UsbUnplugged(deadReason_);  // the type says why, for callers that decide by it
  throw Error(deadReason_);
}

void FalconDevice::lost(const std::exception& e) {
  dead_ = true;
  const bool unplugged = dynamic_cast<const UsbUnplugged*>(&e) != nullptr;
  deadUnplugged_ = unplugged;
  deadReason_ = info().name + " (" + usb_->describe() + ") " + (unplugged ? "was unplugged" : "stopped working") +
                ": " + e.what() + ". Forces are off; open the device again.";
  if (!unplugged) {
    try {  // best effort: leave zero force on a device that may still listen
      const Frame zero = encodeCommand(FalconCommand{});
      serial_.write(zero.data(), zero.size());
    } catch (...) {
    }
  }
  usb_->close();
  throwDead();
}

void FalconDevice::home(double timeout_s) {
  if (!(timeout_s > 0.0 && timeout_s <= 3600.0))
    throw InvalidArgument("homing timeout must be in (0, 3600] s, got " + num(timeout_s));
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_ || dead_) throw Error(info().name + ": home() on a closed or lost device");
  const double start = monotonicNowS();
  while (!state_.homed) {
    std::optional<FalconReport> report;
    try {
      report = exchange();
    } catch (const std::exception& e) {
      lost(e);
    }
    if (report) update(*report);
    if (state_.homed) break;  // not redundant: homed on the last exchange past the deadline is success
    if (monotonicNowS() - start > timeout_s)
      throw Error(info().name + ": not homed after " + num(timeout_s) + " s. With the LED red, pull the grip all "
                  "the way out towards you, then push it all the way in; the LED turns green when homed");
  }
}

DeviceState FalconDevice::read() {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_) throw Error(info().name + ": read() after close()");
  if (dead_) throwDead();
  try {
    if (const auto report = exchange()) update(*report);
  } catch (const std::exception& e) {
    lost(e);
  }
  return state_;
}

void FalconDevice::writeForce(const glm::vec3& force_n) {
  if (!allFinite(force_n))
    throw InvalidArgument(info().name + ": force must be finite (N), got " + vecText(force_n));
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_ || dead_) return;
  command_.motor = {0, 0, 0};
  if (!state_.homed) return;
  glm::dvec3 f(force_n);
  const double magnitude = glm::length(f);
  if (magnitude > opt_.maxForce_n) {
    f *= opt_.maxForce_n / magnitude;
    ++stats_.forceClamps;
  }
  const auto J = kin_.jacobian(glm::dvec3(state_.position_m));
  if (!J) return;  // singular or unreachable pose: no force rather than a wrong one
  const MotorCommand command = FalconKinematics::commandFor(glm::transpose(*J) * f);
  if (command.clamped) ++stats_.commandClamps;
  command_.motor = command.value;
}

void FalconDevice::zeroForce() noexcept {
  try {
    std::lock_guard<std::mutex> lock(mu_);
    command_.motor = {0, 0, 0};
    if (closed_ || dead_) return;
    if (const auto report = exchange()) update(*report);
  } catch (...) {  // the link is failing: read() reports it; close() tries once more
  }
}

void FalconDevice::close() {
  std::lock_guard<std::mutex> lock(mu_);
  if (closed_) return;
  closed_ = true;
  command_ = FalconCommand{};
  if (!dead_) {
    try {  // zero force and LEDs off, with one reply read so the command is through
      const Frame zero = encodeCommand(FalconCommand{});
      serial_.write(zero.data(), zero.size());
      std::uint8_t buf[kFrameBytes];
      serial_.read(buf, sizeof buf, opt_.replyTimeout);
    } catch (...) {
    }
  }
  try {
    usb_->close();
  } catch (...) {
  }
}

}  // namespace hf::haptics::falcon
