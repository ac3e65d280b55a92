// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/falcon_packet.h"

namespace hf::haptics::falcon {
namespace {

constexpr std::uint8_t kStart = '<';
constexpr std::uint8_t kEnd = '>';
constexpr std::uint8_t kBase = 0x41;  // 'A'

void putInt16(Frame& frame, std::size_t first, std::int16_t value) {
  const auto bits = static_cast<std::uint16_t>(value);
  for (std::size_t k = 0; k < 4; ++k) frame[first + k] = static_cast<std::uint8_t>(kBase + ((bits >> (4 * k)) & 0xF));
}

bool nibble(std::uint8_t byte) { return byte >= kBase && byte <= kBase + 0xF; }

// Bytes 1-12 as three int16; false if any byte is not a nibble.
bool getInt16s(const std::uint8_t* data, std::array<std::int16_t, 3>& out) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    std::uint16_t bits = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const std::uint8_t byte = data[1 + 4 * axis + k];
      if (!nibble(byte)) return false;
      bits = static_cast<std::uint16_t>(bits | ((byte - kBase) << (4 * k)));
    }
    out[axis] = static_cast<std::int16_t>(bits);
  }
  return true;
}

bool delimited(const std::uint8_t* data, std::size_t n) {
  return data != nullptr && n == kFrameBytes && data[0] == kStart && data[kFrameBytes - 1] == kEnd;
}

}  // namespace

Frame encodeCommand(const FalconCommand& command) {
  Frame frame{};
  frame[0] = kStart;
  for (std::size_t axis = 0; axis < 3; ++axis) putInt16(frame, 1 + 4 * axis, command.motor[axis]);
  const std::uint8_t flags = static_cast<std::uint8_t>((command.homing ? 0x01 : 0x00) | (command.leds & 0x0E));
  frame[13] = static_cast<std::uint8_t>(kBase + flags);
  frame[14] = kBase;
  frame[15] = kEnd;
  return frame;
}

std::optional<FalconCommand> decodeCommand(const std::uint8_t* data, std::size_t n) {
  if (!delimited(data, n)) return std::nullopt;
  FalconCommand command;
  if (!getInt16s(data, command.motor)) return std::nullopt;
  if (!nibble(data[13])) return std::nullopt;
  const std::uint8_t flags = static_cast<std::uint8_t>(data[13] - kBase);
  command.homing = (flags & 0x01) != 0;
  command.leds = static_cast<std::uint8_t>(flags & 0x0E);
  return command;
}

Frame encodeReport(const FalconReport& report) {
  Frame frame{};
  frame[0] = kStart;
  for (std::size_t axis = 0; axis < 3; ++axis) putInt16(frame, 1 + 4 * axis, report.encoder[axis]);
  const std::uint8_t status = static_cast<std::uint8_t>((report.buttons & 0x0F) | ((report.homed & 0x07) << 4));
  frame[13] = static_cast<std::uint8_t>(kBase + status);
  frame[14] = kBase;
  frame[15] = kEnd;
  return frame;
}

std::optional<FalconReport> decodeReport(const std::uint8_t* data, std::size_t n) {
  if (!delimited(data, n)) return std::nullopt;
  FalconReport report;
  if (!getInt16s(data, report.encoder)) return std::nullopt;
  // Byte 13 carries 7 bits (buttons + homed flags): 0x41 .. 0x41 + 0x7F.
  if (data[13] < kBase || data[13] > kBase + 0x7F) return std::nullopt;
  const std::uint8_t status = static_cast<std::uint8_t>(data[13] - kBase);
  report.buttons = static_cast<std::uint8_t>(status & 0x0F);
  report.homed = static_cast<std::uint8_t>((status >> 4) & 0x07);
  return report;
}

void FrameScanner::push(const std::uint8_t* data, std::size_t n) {
  if (data == nullptr) return;
  pending_.insert(pending_.end(), data, data + n);
}

std::optional<Frame> FrameScanner::pop() {
  std::size_t start = 0;
  std::optional<Frame> found;
  while (start + kFrameBytes <= pending_.size()) {
    const std::uint8_t* p = pending_.data() + start;
    const bool valid = check_ == Check::Report ? decodeReport(p, kFrameBytes).has_value()
                                               : decodeCommand(p, kFrameBytes).has_value();
    if (valid) {
      found.emplace();
      for (std::size_t i = 0; i < kFrameBytes; ++i) (*found)[i] = p[i];
      start += kFrameBytes;
      break;
    }
    ++start;  // not a frame here: drop one byte and look again
    ++dropped_;
  }
  // Drop garbage before a possible frame start even when no whole frame is there yet.
  if (!found) {
    while (start < pending_.size() && pending_[start] != kStart) {
      ++start;
      ++dropped_;
    }
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(start));
  return found;
}

}  // namespace hf::haptics::falcon
