// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// NullDevice: "no device". Its handle rests at the workspace origin, it is homed (there is
// nothing to home) and it accepts and discards forces, so a session runs without hardware.
#include <atomic>

#include "haptics/devices/device.h"

namespace hf::haptics {

class NullDevice : public Device {
 public:
  explicit NullDevice(float max_force_n = 10.0f);
  DeviceInfo info() const override { return info_; }
  DeviceState read() override;  // throws hf::Error after close()
  void writeForce(const glm::vec3& force_n) override;
  void close() override { closed_ = true; }

 private:
  DeviceInfo info_;
  std::atomic<bool> closed_{false};
};

}  // namespace hf::haptics
