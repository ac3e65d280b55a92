// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/devices/null_device.h"

#include <cmath>
#include <string>

#include "common/error.h"
#include "haptics/devices/device_checks.h"
#include "haptics/handoff/clock.h"

namespace hf::haptics {

NullDevice::NullDevice(float max_force_n) {
  checkMaxForce(max_force_n, "null device");
  info_.name = "null";
  info_.kind = "null";
  info_.max_force_n = max_force_n;
}

DeviceState NullDevice::read() {
  if (closed_) throw Error("null device: read after close(); open a new device");
  DeviceState s;
  s.homed = true;
  s.time_s = monotonicNowS();
  return s;
}

void NullDevice::writeForce(const glm::vec3&) {}

}  // namespace hf::haptics
