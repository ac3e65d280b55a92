// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// FTDI FT232R serial port over a UsbTransport: the vendor control requests (bmRequestType 0x40,
// wIndex 0) and a byte stream without the 2 modem-status bytes that begin every 64-byte IN
// packet. Reads are buffered: bytes received beyond what was asked for wait for the next read.
//
// Requests: 0 reset/purge (value 0 reset, 1 purge RX, 2 purge TX), 1 modem control (DTR bit 0,
// RTS bit 1, their write-enable mask in the high byte), 2 flow control (0 = none), 3 baud-rate
// divisor, 4 line settings (0x0008 = 8N1), 9 latency timer (ms).
#include <chrono>
#include <cstdint>
#include <deque>
#include <vector>

#include "haptics/falcon/usb_transport.h"

namespace hf::haptics::falcon {

namespace ftdi {
constexpr std::uint8_t kRequestReset = 0;
constexpr std::uint8_t kRequestModemControl = 1;
constexpr std::uint8_t kRequestFlowControl = 2;
constexpr std::uint8_t kRequestBaudRate = 3;
constexpr std::uint8_t kRequestLineSettings = 4;
constexpr std::uint8_t kRequestLatencyTimer = 9;
constexpr std::uint16_t kResetSio = 0;
constexpr std::uint16_t kPurgeRx = 1;
constexpr std::uint16_t kPurgeTx = 2;
constexpr std::uint16_t kLine8N1 = 0x0008;
constexpr std::uint16_t kDtr = 0x0001;
constexpr std::uint16_t kRts = 0x0002;
constexpr std::size_t kPacketBytes = 64;     // full-speed bulk IN packet
constexpr std::size_t kStatusBytes = 2;      // modem status at the start of every IN packet
}  // namespace ftdi

class FtdiSerial {
 public:
  explicit FtdiSerial(UsbTransport& usb) : usb_(usb) {}

  UsbTransport& transport() { return usb_; }

  void reset();
  // Purges the chip's buffers and this object's read buffer.
  void purge(bool rx, bool tx);
  void setBaudDivisor(std::uint16_t divisor);
  void setLatencyTimer(std::uint8_t ms);
  void setLine8N1();
  void setNoFlowControl();
  void setDtr(bool high);
  void setRts(bool high);

  void write(const std::uint8_t* data, std::size_t n);
  void write(const std::vector<std::uint8_t>& bytes) { write(bytes.data(), bytes.size()); }
  // Up to n bytes into out, waiting at most `timeout` for the first n to arrive; returns how many
  // came (fewer than n only when the timeout passed).
  std::size_t read(std::uint8_t* out, std::size_t n, std::chrono::milliseconds timeout);
  // Bytes already received by earlier transfers and not yet read; no USB traffic, no waiting.
  std::size_t readBuffered(std::uint8_t* out, std::size_t capacity) { return take(out, capacity); }

  unsigned writeTimeoutMs = 100;

 private:
  // One bulk IN transfer; appends its data bytes (status stripped) to buffer_.
  void fill(unsigned timeout_ms);
  std::size_t take(std::uint8_t* out, std::size_t n);

  UsbTransport& usb_;
  std::deque<std::uint8_t> buffer_;
};

}  // namespace hf::haptics::falcon
