// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The byte transport under the Falcon driver: one USB device with a bulk OUT endpoint, a bulk IN
// endpoint and vendor control requests. LibusbTransport talks to the cable; the simulated Falcon
// (simulated_falcon.h) stands in for it in tests. Nothing here knows FTDI or the Falcon.
//
// Wire sequence the layers above produce (see ftdi_serial.h, firmware_loader.h, falcon_device.h):
//   open -> claim interface 0 -> vendor requests (reset/purge, baud, latency, flow, 8N1) ->
//   [bootloader: DTR/RTS toggles, 0A 43 0D handshake, 'A', firmware bytes echoed] ->
//   normal mode (latency 1 ms, baud divisor 2, purge) -> 16-byte command / 16-byte reply, ~1 kHz.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"

namespace hf::haptics::falcon {

// The device disappeared (unplugged, powered off): every later call fails the same way.
class UsbUnplugged : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

// The user may not open the device (no udev rule); the message prints the rule to install.
class UsbAccessDenied : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

// No device of the kind asked for is plugged in.
class UsbNotFound : public DeviceError {
 public:
  using DeviceError::DeviceError;
};

class UsbTransport {
 public:
  virtual ~UsbTransport() = default;
  // Opens the device and claims its interface; throws hf::Error naming the stage.
  virtual void open() = 0;
  // Releases the interface and the handle. Idempotent; never throws.
  virtual void close() = 0;
  virtual bool isOpen() const = 0;
  // Vendor OUT control request (bmRequestType 0x40) with no data stage.
  virtual void controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index) = 0;
  // Bulk OUT: writes all n bytes or throws (a timeout is an error here).
  virtual void bulkWrite(const std::uint8_t* data, std::size_t n, unsigned timeout_ms) = 0;
  // Bulk IN: up to `capacity` bytes (FTDI status bytes included); 0 when the timeout passed
  // with nothing received.
  virtual std::size_t bulkRead(std::uint8_t* out, std::size_t capacity, unsigned timeout_ms) = 0;
  // For messages: "USB bus 1 address 7", "simulated Falcon".
  virtual std::string describe() const = 0;
};

}  // namespace hf::haptics::falcon
