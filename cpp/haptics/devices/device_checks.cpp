// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/devices/device_checks.h"

#include <cmath>

#include "common/error.h"

namespace hf::haptics {

void checkMaxForce(float max_force_n, const std::string& who) {
  if (!std::isfinite(max_force_n) || max_force_n <= 0.0f || max_force_n > kMaxDeviceForceN) {
    throw InvalidArgument(who + ": max_force must be a positive number of newtons, at most " +
                          std::to_string(kMaxDeviceForceN) + ", got " + std::to_string(max_force_n));
  }
}

}  // namespace hf::haptics
