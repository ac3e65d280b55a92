// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// DeviceClaim: exclusive use of a Device for a scope. A second haptic loop on the same device,
// or a host's write_force() while a session drives it, would command force past the running
// session's safety stage (no slew, no ramp) and race on a device made for one thread; the
// claim turns both into a clear error instead.
#include <string>

#include "haptics/devices/device.h"

namespace hf::haptics {

class DeviceClaim {
 public:
  // Throws hf::Error naming the device and `action` (what the caller was about to do) if the
  // device is held already.
  DeviceClaim(Device& device, const std::string& action);
  ~DeviceClaim() { device_.releaseClaim(); }
  DeviceClaim(const DeviceClaim&) = delete;
  DeviceClaim& operator=(const DeviceClaim&) = delete;

 private:
  Device& device_;
};

}  // namespace hf::haptics
