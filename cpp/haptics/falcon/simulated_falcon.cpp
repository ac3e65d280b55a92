// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/simulated_falcon.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <string>
#include <thread>

#include "haptics/falcon/firmware_loader.h"
#include "haptics/falcon/ftdi_serial.h"

namespace hf::haptics::falcon {
namespace {

constexpr std::uint8_t kModemStatus[2] = {0x01, 0x60};
constexpr double kPi = 3.14159265358979323846;
constexpr double kGestureDuration_s = kHomingGestureS;
constexpr double kGestureReach_m = 0.035;

std::string pointText(const glm::dvec3& p) {
  return "(" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ")";
}

}  // namespace

glm::dvec3 homingGesture(double t_s) {
  if (t_s <= 0.0 || t_s >= kGestureDuration_s) return glm::dvec3(0.0);
  return {0.0, 0.0, kGestureReach_m * std::sin(kPi * t_s / kGestureDuration_s)};
}

std::function<glm::dvec3(double)> scriptedHand(std::vector<HandWaypoint> w, bool loop) {
  if (w.empty()) throw InvalidArgument("hand_path needs at least one waypoint (t, x, y, z) in s and m");
  if (loop && w.size() < 2) throw InvalidArgument("hand_path needs at least two waypoints to loop");
  const FalconKinematics kin;
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double t = w[i].time_s;
    if (!std::isfinite(t) || t < 0.0 || (i > 0 && !(t > w[i - 1].time_s))) {
      throw InvalidArgument("hand_path waypoint " + std::to_string(i) + ": its time " + std::to_string(t) +
                            " s must be finite, >= 0 and after the waypoint before (times in s, increasing)");
    }
    const glm::dvec3& p = w[i].position_m;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !kin.inverse(p)) {
      throw InvalidArgument("hand_path waypoint " + std::to_string(i) + " " + pointText(p) +
                            " m is out of the Falcon's reach: keep waypoints within about 0.04 m of the workspace "
                            "centre (device frame, m)");
    }
  }
  // A loop runs over the given waypoints; before the first one the hand moves from the centre
  // (where homing leaves it) towards it.
  const double start = w.front().time_s, period = w.back().time_s - start;
  if (w.front().time_s > 0.0) w.insert(w.begin(), HandWaypoint{0.0, glm::dvec3(0.0)});
  return [w = std::move(w), loop, start, period](double t_s) -> glm::dvec3 {
    if (t_s < kGestureDuration_s) return homingGesture(t_s);
    double t = t_s - kGestureDuration_s;
    if (loop && period > 0.0 && t > w.back().time_s) t = start + std::fmod(t - start, period);
    if (t >= w.back().time_s) return w.back().position_m;
    if (t <= w.front().time_s) return w.front().position_m;
    const auto next = std::upper_bound(w.begin(), w.end(), t,
                                       [](double v, const HandWaypoint& p) { return v < p.time_s; });
    const HandWaypoint& b = *next;
    const HandWaypoint& a = *(next - 1);
    const double f = (t - a.time_s) / (b.time_s - a.time_s);
    return a.position_m + f * (b.position_m - a.position_m);
  };
}

SimulatedFalconTransport::SimulatedFalconTransport(SimulatedFalconOptions options)
    : opt_(std::move(options)),
      mode_(opt_.expectedFirmware.empty() ? Mode::Running : Mode::Bootloader) {
  if (!opt_.handPath) opt_.handPath = homingGesture;
  const bool finite = std::isfinite(opt_.packetDt_s) && std::isfinite(opt_.handMass_kg) &&
                      std::isfinite(opt_.handStiffness_n_m) && std::isfinite(opt_.handDamping_n_s_m);
  if (!(finite && opt_.packetDt_s > 0.0 && opt_.handMass_kg > 0.0 && opt_.handStiffness_n_m >= 0.0 &&
        opt_.handDamping_n_s_m >= 0.0))
    throw InvalidArgument("simulated Falcon: packet time step (s) and hand mass (kg) must be positive and finite, "
                          "hand stiffness (N/m) and damping (N s/m) finite and non-negative");
  const auto home = kin_.inverse(glm::dvec3(0.0, 0.0, opt_.homingPullOut_m));
  if (!home) throw InvalidArgument("simulated Falcon: the homing pull-out point is outside the workspace");
  homeAngles_ = *home;
  s_.firmwareRunning = mode_ == Mode::Running;
  s_.position_m = opt_.handPath(0.0);
  if (!kin_.inverse(s_.position_m)) throw InvalidArgument("simulated Falcon: the hand path starts out of reach");
}

void SimulatedFalconTransport::checkPlugged() const {
  if (s_.unplugged) throw UsbUnplugged("simulated Novint Falcon: LIBUSB_ERROR_NO_DEVICE: the Falcon was unplugged");
}

void SimulatedFalconTransport::open() {
  std::lock_guard<std::mutex> lock(mu_);
  checkPlugged();
  open_ = true;
}

void SimulatedFalconTransport::close() {
  std::lock_guard<std::mutex> lock(mu_);
  open_ = false;
}

bool SimulatedFalconTransport::isOpen() const {
  std::lock_guard<std::mutex> lock(mu_);
  return open_;
}

void SimulatedFalconTransport::unplug() {
  std::lock_guard<std::mutex> lock(mu_);
  s_.unplugged = true;
}

SimulatedFalconState SimulatedFalconTransport::state() const {
  std::lock_guard<std::mutex> lock(mu_);
  return s_;
}

double SimulatedFalconTransport::time_s() const {
  std::lock_guard<std::mutex> lock(mu_);
  return s_.time_s;
}

void SimulatedFalconTransport::resetDsp() {
  mode_ = Mode::Bootloader;
  s_.firmwareRunning = false;
  s_.homed = 0;
  s_.firmwareBytes = 0;
  received_.clear();
  fromHost_.clear();
  commands_.clear();
  stalled_ = false;
}

void SimulatedFalconTransport::controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t /*index*/) {
  std::lock_guard<std::mutex> lock(mu_);
  checkPlugged();
  if (!open_) throw Error("simulated Novint Falcon: control request before open()");
  switch (request) {
    case ftdi::kRequestReset:
      if (value == ftdi::kResetSio || value == ftdi::kPurgeRx) toHost_.clear();
      break;
    case ftdi::kRequestModemControl:
      if ((value >> 8) & ftdi::kDtr) {
        const bool high = (value & ftdi::kDtr) != 0;
        if (high && !dtr_) resetDsp();  // DTR drives the DSP's reset into its bootloader
        dtr_ = high;
      }
      break;
    case ftdi::kRequestBaudRate:
      s_.baudDivisor = value;
      if (value == kBaudNormal && mode_ == Mode::Streaming) {
        const bool good = !opt_.expectedFirmware.empty() && received_ == opt_.expectedFirmware;
        mode_ = good ? Mode::Running : Mode::Crashed;
        s_.firmwareRunning = good;
      }
      break;
    case ftdi::kRequestLatencyTimer:
      s_.latency_ms = static_cast<std::uint8_t>(value);
      break;
    default:
      break;  // flow control, line settings: accepted
  }
}

void SimulatedFalconTransport::bootloaderBytes(const std::uint8_t* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t byte = data[i];
    if ((mode_ == Mode::Bootloader || mode_ == Mode::AwaitBaudLock) && s_.baudDivisor == kBaudBootloader) {
      fromHost_.push_back(byte);
      const std::size_t k = fromHost_.size();
      const bool hello = k >= sizeof kHello && std::equal(std::begin(kHello), std::end(kHello),
                                                           fromHost_.end() - static_cast<std::ptrdiff_t>(sizeof kHello));
      if (hello) {
        fromHost_.clear();
        if (!opt_.faults.silentBootloader) {
          toHost_.insert(toHost_.end(), std::begin(kHelloReply), std::end(kHelloReply));
          mode_ = Mode::AwaitBaudLock;
          ++s_.handshakes;
          received_.clear();
          s_.firmwareBytes = 0;
          stalled_ = false;
        }
      }
    } else if (mode_ == Mode::AwaitBaudLock && s_.baudDivisor == kBaudUpload) {
      if (byte == kAutobaud) {
        toHost_.push_back(byte);
        mode_ = Mode::Streaming;
      }
    } else if (mode_ == Mode::Streaming && s_.baudDivisor == kBaudUpload) {
      const long index = static_cast<long>(received_.size());
      if (index == opt_.faults.unplugAtFirmwareByte) {
        s_.unplugged = true;
        checkPlugged();
      }
      if (!stalled_ && index == opt_.faults.stallEchoAtByte && stalledUploads_ < opt_.faults.stallEchoUploads) {
        stalled_ = true;
        ++stalledUploads_;
      }
      if (stalled_) continue;
      std::uint8_t echo = byte;
      if (index == opt_.faults.corruptEchoAtByte && corruptedUploads_ < opt_.faults.corruptEchoUploads) {
        echo = static_cast<std::uint8_t>(echo ^ 0x5A);
        ++corruptedUploads_;
      }
      received_.push_back(byte);
      s_.firmwareBytes = received_.size();
      toHost_.push_back(echo);
    }
    // Any other mode or baud rate: the byte is garbage to the DSP and ignored.
  }
}

void SimulatedFalconTransport::stepHand(const glm::dvec3& motor_force_n) {
  const double dt = opt_.packetDt_s;
  const glm::dvec3 target = opt_.handPath(s_.time_s);
  const bool relaxed = opt_.handStiffnessHomed_n_m >= 0.0 && s_.homed == 0x7;
  const double stiffness = relaxed ? opt_.handStiffnessHomed_n_m : opt_.handStiffness_n_m;
  const glm::dvec3 hand = stiffness * (target - s_.position_m) - opt_.handDamping_n_s_m * s_.velocity_m_s;
  s_.velocity_m_s += dt * (motor_force_n + hand) / opt_.handMass_kg;
  const glm::dvec3 next = s_.position_m + dt * s_.velocity_m_s;
  if (kin_.inverse(next))
    s_.position_m = next;
  else
    s_.velocity_m_s = glm::dvec3(0.0);  // the mechanism's end stop
  s_.time_s += dt;
}

void SimulatedFalconTransport::answer(const FalconCommand& command) {
  s_.lastCommand = command;
  s_.leds = command.leds;
  s_.homingMode = command.homing;
  // Motor torques act on the grip: F = J^-T tau.
  glm::dvec3 force(0.0);
  if (const auto jinv = kin_.inverseJacobian(s_.position_m))
    force = glm::transpose(*jinv) * FalconKinematics::torqueFromCommand(command.motor);
  s_.motorForce_n = force;
  stepHand(force);
  const auto angles = kin_.inverse(s_.position_m);
  FalconReport report;
  if (angles) {
    for (int i = 0; i < 3; ++i) {
      if (command.homing && (*angles)[i] >= homeAngles_[i]) s_.homed = static_cast<std::uint8_t>(s_.homed | (1u << i));
      const auto count = FalconKinematics::countFromAngle((*angles)[i]);
      int value = count ? *count : 0;
      if (!(s_.homed & (1u << i))) value += opt_.powerOnOffset[static_cast<std::size_t>(i)];
      report.encoder[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(static_cast<std::uint16_t>(value));
    }
  }
  report.homed = s_.homed;
  report.buttons = static_cast<std::uint8_t>(opt_.buttons ? (opt_.buttons(s_.time_s) & 0x0F) : 0);
  const long index = s_.packets++;
  const auto& f = opt_.faults;
  const bool dropped = f.dropRepliesFrom >= 0 && index >= f.dropRepliesFrom && index < f.dropRepliesFrom + f.dropRepliesCount;
  if (!dropped) {
    const Frame frame = encodeReport(report);
    toHost_.insert(toHost_.end(), frame.begin(), frame.end());
  }
  if (f.unplugAtPacket >= 0 && s_.packets >= f.unplugAtPacket) s_.unplugged = true;
}

void SimulatedFalconTransport::runningBytes(const std::uint8_t* data, std::size_t n) {
  if (s_.baudDivisor != kBaudNormal) return;
  commands_.push(data, n);
  while (const auto frame = commands_.pop()) {
    if (const auto command = decodeCommand(frame->data(), frame->size())) answer(*command);
    if (s_.unplugged) return;
  }
}

void SimulatedFalconTransport::bulkWrite(const std::uint8_t* data, std::size_t n, unsigned /*timeout_ms*/) {
  std::lock_guard<std::mutex> lock(mu_);
  checkPlugged();
  if (!open_) throw Error("simulated Novint Falcon: write before open()");
  if (mode_ == Mode::Running)
    runningBytes(data, n);
  else if (mode_ != Mode::Crashed)
    bootloaderBytes(data, n);
}

std::size_t SimulatedFalconTransport::bulkRead(std::uint8_t* out, std::size_t capacity, unsigned timeout_ms) {
  if (capacity < 2) throw InvalidArgument("simulated Novint Falcon: a bulk read needs room for the 2 status bytes");
  unsigned latency = 1;
  {
    std::lock_guard<std::mutex> lock(mu_);
    checkPlugged();
    if (!open_) throw Error("simulated Novint Falcon: read before open()");
    if (!toHost_.empty()) {
      out[0] = kModemStatus[0];
      out[1] = kModemStatus[1];
      const std::size_t n = std::min(capacity, ftdi::kPacketBytes) - 2;
      const std::size_t k = std::min(n, toHost_.size());
      std::copy_n(toHost_.begin(), k, out + 2);
      toHost_.erase(toHost_.begin(), toHost_.begin() + static_cast<std::ptrdiff_t>(k));
      return k + 2;
    }
    latency = std::max<unsigned>(1, s_.latency_ms);
  }
  // Like the chip: with nothing to send, a status-only packet when the latency timer expires.
  std::this_thread::sleep_for(std::chrono::milliseconds(std::min(latency, std::max(1u, timeout_ms))));
  std::lock_guard<std::mutex> lock(mu_);
  checkPlugged();
  out[0] = kModemStatus[0];
  out[1] = kModemStatus[1];
  return 2;
}

}  // namespace hf::haptics::falcon
