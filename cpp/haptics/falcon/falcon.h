// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The Falcon folder's public header: find Falcons, open one, or open the simulated Falcon.
// Layers below (each testable alone): usb_transport / libusb_transport (comm), ftdi_serial,
// firmware_loader + falcon_packet (firmware), falcon_kinematics (math), falcon_device (device),
// simulated_falcon (a Falcon behind the transport interface).
#include <optional>
#include <string>
#include <vector>

#include "haptics/falcon/falcon_device.h"
#include "haptics/falcon/simulated_falcon.h"

namespace hf::haptics::falcon {

struct FalconListing {
  int index = 0;                       // for openFalcon()
  int bus = 0;
  int address = 0;
  std::string serial;                  // empty if unknown
  bool permissionOk = true;            // false: no udev rule (see udevRule)
  std::optional<bool> firmwareLoaded;  // nullopt: not checked or could not be checked
  std::string problem;                 // empty, or what stands in the way, with what to do
};

// Every Falcon plugged in. probeFirmware opens each one and exchanges a few zero-force packets.
// None plugged in -> an empty list (not an error).
std::vector<FalconListing> listFalcons(bool probeFirmware = true);

// The udev rule text and how to install it.
std::string udevRule();

// Opens Falcon number `index` of listFalcons(). Errors: none plugged in / index out of range
// (hf::InvalidArgument when Falcons exist but not that many), permission (UsbAccessDenied with
// the udev rule), firmware, homing.
std::shared_ptr<FalconDevice> openFalcon(int index, FalconOptions options);

// The whole driver on a simulated Falcon; `transport` stays inspectable by the caller. Readings
// are stamped with options.clock (default: the steady clock, as for hardware; simulatedClock()
// makes them the simulation's time, packetDt_s per packet, for deterministic tests).
std::shared_ptr<FalconDevice> openSimulatedFalcon(const std::shared_ptr<SimulatedFalconTransport>& transport,
                                                  FalconOptions options);
std::function<double()> simulatedClock(const std::shared_ptr<SimulatedFalconTransport>& transport);

}  // namespace hf::haptics::falcon
