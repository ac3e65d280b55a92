// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/falcon/ftdi_serial.h"

#include <algorithm>

namespace hf::haptics::falcon {

void FtdiSerial::reset() {
  usb_.controlOut(ftdi::kRequestReset, ftdi::kResetSio, 0);
  buffer_.clear();
}

void FtdiSerial::purge(bool rx, bool tx) {
  if (rx) usb_.controlOut(ftdi::kRequestReset, ftdi::kPurgeRx, 0);
  if (tx) usb_.controlOut(ftdi::kRequestReset, ftdi::kPurgeTx, 0);
  if (rx) buffer_.clear();
}

void FtdiSerial::setBaudDivisor(std::uint16_t divisor) { usb_.controlOut(ftdi::kRequestBaudRate, divisor, 0); }

void FtdiSerial::setLatencyTimer(std::uint8_t ms) { usb_.controlOut(ftdi::kRequestLatencyTimer, ms, 0); }

void FtdiSerial::setLine8N1() { usb_.controlOut(ftdi::kRequestLineSettings, ftdi::kLine8N1, 0); }

void FtdiSerial::setNoFlowControl() { usb_.controlOut(ftdi::kRequestFlowControl, 0, 0); }

void FtdiSerial::setDtr(bool high) {
  usb_.controlOut(ftdi::kRequestModemControl, static_cast<std::uint16_t>((ftdi::kDtr << 8) | (high ? ftdi::kDtr : 0)), 0);
}

void FtdiSerial::setRts(bool high) {
  usb_.controlOut(ftdi::kRequestModemControl, static_cast<std::uint16_t>((ftdi::kRts << 8) | (high ? ftdi::kRts : 0)), 0);
}

void FtdiSerial::write(const std::uint8_t* data, std::size_t n) { usb_.bulkWrite(data, n, writeTimeoutMs); }

void FtdiSerial::fill(unsigned timeout_ms) {
  std::uint8_t raw[ftdi::kPacketBytes];
  const std::size_t got = usb_.bulkRead(raw, sizeof raw, timeout_ms);
  // Every packet of the transfer (one here, at most 64 bytes) starts with 2 status bytes.
  for (std::size_t start = 0; start < got; start += ftdi::kPacketBytes) {
    const std::size_t end = std::min(got, start + ftdi::kPacketBytes);
    for (std::size_t i = start + ftdi::kStatusBytes; i < end; ++i) buffer_.push_back(raw[i]);
  }
}

std::size_t FtdiSerial::take(std::uint8_t* out, std::size_t n) {
  const std::size_t k = std::min(n, buffer_.size());
  std::copy_n(buffer_.begin(), k, out);
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(k));
  return k;
}

std::size_t FtdiSerial::read(std::uint8_t* out, std::size_t n, std::chrono::milliseconds timeout) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + timeout;
  std::size_t done = take(out, n);
  // At least one look at the device, even if the deadline passed before it (this thread was
  // preempted, or timeout is 0): a reply that is already waiting is not a missed reply.
  for (bool looked = false; done < n; looked = true) {
    const auto now = Clock::now();
    if (looked && now >= deadline) break;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - now).count();
    fill(static_cast<unsigned>(std::max<long long>(1, left)));  // 1 ms at least (0 is "forever" to libusb)
    done += take(out + done, n - done);
  }
  return done;
}

}  // namespace hf::haptics::falcon
