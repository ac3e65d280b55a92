// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Firmware upload through the DSP's ROM serial bootloader (TI C28x), over FtdiSerial:
//   1. purge RX/TX; latency 16 ms; baud divisor 0x4138 (9600); 8N1; no flow control
//   2. RTS low, DTR low, DTR high
//   3. send 0A 43 0D, expect 0A 44 2C 0D (a leading 00 is tolerated); up to handshakeTries
//   4. DTR low; baud divisor 0x0015 (~140 kbaud)
//   5. send 'A' (0x41): the bootloader locks its baud rate and echoes it
//   6. stream the image in writes of at most 62 bytes, comparing every echoed byte
//   7. normal mode: latency 1 ms, baud divisor 0x0002 (~1.456 Mbaud), purge
// The image is the user's file (Novint's firmware may not be redistributed; none ships here).
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "haptics/falcon/ftdi_serial.h"

namespace hf::haptics::falcon {

// FTDI baud-rate divisors of the three phases (steps 1, 4 and 7).
constexpr std::uint16_t kBaudBootloader = 0x4138;  // 9600 baud
constexpr std::uint16_t kBaudUpload = 0x0015;      // ~140 kbaud
constexpr std::uint16_t kBaudNormal = 0x0002;      // ~1.456 Mbaud
// The bootloader's handshake (step 3) and baud-lock byte (step 5).
inline constexpr std::uint8_t kHello[] = {0x0A, 0x43, 0x0D};
inline constexpr std::uint8_t kHelloReply[] = {0x0A, 0x44, 0x2C, 0x0D};
constexpr std::uint8_t kAutobaud = 0x41;  // 'A'

// Largest image accepted (the known ones are 7,324 and 8,492 bytes).
constexpr std::size_t kMaxFirmwareBytes = 64 * 1024;

// The file's bytes. hf::InvalidArgument (saying what to change) when it is missing, not a regular
// file, unreadable, empty or larger than kMaxFirmwareBytes.
std::vector<std::uint8_t> readFirmwareFile(const std::string& path);

// Puts the FTDI into the Falcon's normal packet mode (step 7).
void enterNormalMode(FtdiSerial& serial);

struct FirmwareLoaderOptions {
  int handshakeTries = 100;
  int uploadAttempts = 10;                         // whole uploads before giving up
  std::chrono::milliseconds handshakeTimeout{100};  // per handshake reply
  std::chrono::milliseconds echoTimeout{500};       // per chunk echo
};

class FirmwareLoader {
 public:
  explicit FirmwareLoader(FtdiSerial& serial, FirmwareLoaderOptions options = {})
      : serial_(serial), options_(options) {}

  // Uploads and leaves the FTDI in normal mode; throws hf::Error after the last failed attempt
  // with the reason of each (no handshake, echo mismatch at byte k, timeout) and what to do.
  // hf::InvalidArgument for an empty or oversized image.
  void upload(const std::vector<std::uint8_t>& image);

  int attemptsUsed() const { return attempts_; }

 private:
  // One attempt; returns "" on success or why it failed. Unplug propagates as UsbUnplugged.
  std::string attempt(const std::vector<std::uint8_t>& image);
  bool handshake();

  FtdiSerial& serial_;
  FirmwareLoaderOptions options_;
  int attempts_ = 0;
};

}  // namespace hf::haptics::falcon
