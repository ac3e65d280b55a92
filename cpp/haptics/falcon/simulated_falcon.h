// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A Novint Falcon simulated behind the USB transport, so the whole driver (FTDI setup, firmware
// upload, homing, packets, kinematics) runs without hardware. It answers the FTDI requests (baud,
// latency, purge, DTR/RTS), the DSP bootloader (handshake at 9600 baud, 'A' baud lock, byte echo
// at ~140 kbaud; a DTR rising edge resets the DSP into the bootloader), then, once the uploaded
// image equals the expected one and the host switches to divisor 2, one 16-byte reply per
// 16-byte command from a simulated mechanism:
//   - the grip is held by a hand: a mass pulled by a spring-damper towards a scripted path;
//   - motor commands -> arm torques -> force on the grip through the Jacobian (F = J^-T tau);
//   - grip position -> encoder counts by inverse kinematics, offset until the axis is homed;
//   - homing: with the homing bit set, an axis homes when its arm passes the pulled-out angle.
// Simulated time advances packetDt per packet. Faults can be injected (see SimulatedFalconFaults).
// Thread-safe: tests may inspect state() while a device uses the transport.
#include <functional>
#include <mutex>
#include <vector>

#include "haptics/falcon/falcon_kinematics.h"
#include "haptics/falcon/falcon_packet.h"
#include "haptics/falcon/usb_transport.h"

namespace hf::haptics::falcon {

struct SimulatedFalconFaults {
  long corruptEchoAtByte = -1;     // firmware byte whose echo is wrong ...
  int corruptEchoUploads = 1;      // ... in this many uploads (a large number: every upload)
  long stallEchoAtByte = -1;       // the echo stops at this byte (the host times out) ...
  int stallEchoUploads = 1;        // ... in this many uploads
  bool silentBootloader = false;   // the bootloader never answers the handshake
  long unplugAtPacket = -1;        // unplugged when this many packets (running mode) were answered
  long unplugAtFirmwareByte = -1;  // unplugged when the upload reaches this byte
  long dropRepliesFrom = -1;       // from this packet on, no replies ...
  long dropRepliesCount = 0;       // ... for this many packets
};

struct SimulatedFalconOptions {
  // Empty: the firmware is already running at power-up. Otherwise the DSP sits in its bootloader
  // until exactly these bytes are uploaded.
  std::vector<std::uint8_t> expectedFirmware;
  double packetDt_s = 0.001;
  double handMass_kg = 0.15;
  double handStiffness_n_m = 300.0;
  double handDamping_n_s_m = 12.0;
  // The hand's stiffness once all three axes are homed (N/m); < 0: handStiffness_n_m throughout. A
  // user who homes the Falcon and then rests the hand lightly on the grip (the playback guide's tests).
  double handStiffnessHomed_n_m = -1.0;
  // Where the hand pulls the grip (device frame, m) at simulated time t (s). Empty: homingGesture.
  std::function<glm::dvec3(double)> handPath;
  std::function<std::uint32_t(double)> buttons;  // grip buttons pressed at time t (button:: bits)
  std::array<std::int16_t, 3> powerOnOffset{417, -1203, 2290};  // counts added until homed
  double homingPullOut_m = 0.03;  // device-frame z where the arms pass their homing index
  SimulatedFalconFaults faults;
};

// The hand path of a user homing the Falcon: from the centre out to z = 0.035 m and back in over
// 0.6 s, then resting at the centre.
glm::dvec3 homingGesture(double t_s);
inline constexpr double kHomingGestureS = 0.6;  // its length, s

// One waypoint of a scripted hand: where the hand pulls the grip (device frame, m) at a time (s).
struct HandWaypoint {
  double time_s = 0.0;
  glm::dvec3 position_m{0.0};
};

// The hand of a user who homes the Falcon (homingGesture, kHomingGestureS) and then follows the
// waypoints (time 0 = the end of the homing gesture), linearly interpolated; before the first
// waypoint's time the hand moves from the centre towards it; after the last it holds it, or with
// `loop` starts over at the first (two waypoints at least). Throws InvalidArgument naming
// hand_path (the waypoint's index): none given, a time that is not finite, negative or not after
// the one before, a position that is not finite or out of the Falcon's reach (+-0.04 m about
// the workspace centre, checked by its kinematics).
std::function<glm::dvec3(double)> scriptedHand(std::vector<HandWaypoint> waypoints, bool loop);

struct SimulatedFalconState {
  bool unplugged = false;
  bool firmwareRunning = false;
  int handshakes = 0;              // bootloader handshakes answered (one per upload attempt)
  std::size_t firmwareBytes = 0;   // bytes received in the current upload
  long packets = 0;                // commands answered
  double time_s = 0.0;
  glm::dvec3 position_m{0.0};      // true grip position, device frame
  glm::dvec3 velocity_m_s{0.0};
  glm::dvec3 motorForce_n{0.0};    // force of the motors on the grip in the last packet
  std::uint8_t homed = 0;
  std::uint8_t leds = 0;
  bool homingMode = false;
  FalconCommand lastCommand;
  std::uint16_t baudDivisor = 0;
  std::uint8_t latency_ms = 16;
};

class SimulatedFalconTransport : public UsbTransport {
 public:
  explicit SimulatedFalconTransport(SimulatedFalconOptions options = {});

  void open() override;
  void close() override;
  bool isOpen() const override;
  void controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index) override;
  void bulkWrite(const std::uint8_t* data, std::size_t n, unsigned timeout_ms) override;
  std::size_t bulkRead(std::uint8_t* out, std::size_t capacity, unsigned timeout_ms) override;
  std::string describe() const override { return "simulated Novint Falcon"; }

  SimulatedFalconState state() const;
  double time_s() const;
  void unplug();

 private:
  enum class Mode { Bootloader, AwaitBaudLock, Streaming, Running, Crashed };

  void checkPlugged() const;
  void bootloaderBytes(const std::uint8_t* data, std::size_t n);
  void runningBytes(const std::uint8_t* data, std::size_t n);
  void answer(const FalconCommand& command);
  void stepHand(const glm::dvec3& motor_force_n);
  void resetDsp();

  SimulatedFalconOptions opt_;
  FalconKinematics kin_;
  glm::dvec3 homeAngles_{0.0};
  mutable std::mutex mu_;
  bool open_ = false;
  Mode mode_;
  SimulatedFalconState s_;
  std::vector<std::uint8_t> toHost_;
  std::vector<std::uint8_t> fromHost_;     // bootloader handshake bytes
  std::vector<std::uint8_t> received_;     // uploaded image so far
  FrameScanner commands_{FrameScanner::Check::Command};
  int corruptedUploads_ = 0;
  int stalledUploads_ = 0;
  bool stalled_ = false;
  bool dtr_ = false;
};

}  // namespace hf::haptics::falcon
