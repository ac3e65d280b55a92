// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The Falcon's 16-byte frames (test and nVent firmware share them): '<', 14 payload bytes, '>'.
// Bytes 1-12: three int16 as 4 nibbles each, least significant first, nibble + 0x41 ('A'..'P').
// Host -> device: motor commands; byte 13 = flags + 0x41 (0x01 homing, 0x02 green, 0x04 blue,
// 0x08 red LED); byte 14 'A'. Device -> host: encoder counts; byte 13 - 0x41: low nibble grip
// buttons, bits 4-6 homed flags of the three axes; byte 14 unknown (not checked).
// There is no checksum: a frame is valid when its delimiters and every checked byte are in range.
// Decoding never throws and never reads outside the given bytes: malformed input -> nullopt.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace hf::haptics::falcon {

constexpr std::size_t kFrameBytes = 16;
using Frame = std::array<std::uint8_t, kFrameBytes>;

namespace led {
constexpr std::uint8_t kGreen = 0x02;
constexpr std::uint8_t kBlue = 0x04;
constexpr std::uint8_t kRed = 0x08;
}  // namespace led

namespace button {
constexpr std::uint32_t kRight = 0x1;    // plus
constexpr std::uint32_t kForward = 0x2;
constexpr std::uint32_t kCentre = 0x4;
constexpr std::uint32_t kLeft = 0x8;     // minus
}  // namespace button

struct FalconCommand {
  std::array<std::int16_t, 3> motor{};   // per arm; unit undocumented (see falcon_kinematics.h)
  std::uint8_t leds = 0;                 // led:: bits
  bool homing = false;
};

struct FalconReport {
  std::array<std::int16_t, 3> encoder{};  // counts per arm
  std::uint8_t buttons = 0;               // button:: bits (low nibble)
  std::uint8_t homed = 0;                 // bit i: axis i homed
  bool allHomed() const { return homed == 0x7; }
};

Frame encodeCommand(const FalconCommand& command);
std::optional<FalconCommand> decodeCommand(const std::uint8_t* data, std::size_t n);
Frame encodeReport(const FalconReport& report);
std::optional<FalconReport> decodeReport(const std::uint8_t* data, std::size_t n);

// Cuts a byte stream into frames: push what arrived, pop whole valid frames. Bytes that cannot
// start a valid frame are dropped (counted), so a lost or garbled byte costs one frame, not sync.
class FrameScanner {
 public:
  void push(const std::uint8_t* data, std::size_t n);
  // The oldest complete valid frame, if any.
  std::optional<Frame> pop();
  void clear() { pending_.clear(); }
  std::size_t droppedBytes() const { return dropped_; }

  // Which decoder decides validity while scanning: reports (host side) or commands (simulator).
  enum class Check { Report, Command };
  explicit FrameScanner(Check check = Check::Report) : check_(check) {}

 private:
  Check check_;
  std::vector<std::uint8_t> pending_;
  std::size_t dropped_ = 0;
};

}  // namespace hf::haptics::falcon
