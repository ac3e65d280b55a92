// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/devices/device_claim.h"

#include "common/error.h"

namespace hf::haptics {

DeviceClaim::DeviceClaim(Device& device, const std::string& action) : device_(device) {
  if (!device.tryClaim()) {
    throw Error("device '" + device.info().name + "' is in use (a running HapticSession drives it, or another call "
                "on it has not returned): cannot " + action + "; stop that session first, or give this one its "
                "own device");
  }
}

}  // namespace hf::haptics
