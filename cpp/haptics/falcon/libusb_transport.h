// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// UsbTransport over libusb-1.0: the Falcon's FT232R (0403:cb48), interface 0, bulk OUT 0x02,
// bulk IN 0x81. Owns its libusb context and device handle (RAII). Every libusb failure becomes an
// hf::Error naming the stage and libusb_error_name(); LIBUSB_ERROR_ACCESS becomes UsbAccessDenied
// with the udev rule to install, LIBUSB_ERROR_NO_DEVICE becomes UsbUnplugged.
#include <memory>
#include <string>
#include <vector>

#include "haptics/falcon/usb_transport.h"

namespace hf::haptics::falcon {

constexpr std::uint16_t kFalconVendorId = 0x0403;
constexpr std::uint16_t kFalconProductId = 0xcb48;

// The rule that gives logged-in users access to the Falcon, with where to put it.
std::string udevRuleHelp();

// One Falcon found on the bus. Reading its serial needs opening it, which is where a missing
// udev rule shows up (access_denied).
struct UsbFalconEntry {
  int bus = 0;
  int address = 0;
  std::string serial;        // empty when it could not be read
  bool access_denied = false;
  std::string problem;       // empty, or why it could not be opened
};

// Every 0403:cb48 on the system, in bus/address order. No Falcon -> empty list, not an error;
// throws hf::Error only if libusb itself cannot start.
std::vector<UsbFalconEntry> findUsbFalcons();

class LibusbTransport : public UsbTransport {
 public:
  // The Falcon at this bus and address (from findUsbFalcons()); opened by open().
  LibusbTransport(int bus, int address);
  ~LibusbTransport() override;
  LibusbTransport(const LibusbTransport&) = delete;
  LibusbTransport& operator=(const LibusbTransport&) = delete;

  void open() override;
  void close() override;
  bool isOpen() const override;
  void controlOut(std::uint8_t request, std::uint16_t value, std::uint16_t index) override;
  void bulkWrite(const std::uint8_t* data, std::size_t n, unsigned timeout_ms) override;
  std::size_t bulkRead(std::uint8_t* out, std::size_t capacity, unsigned timeout_ms) override;
  std::string describe() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hf::haptics::falcon
