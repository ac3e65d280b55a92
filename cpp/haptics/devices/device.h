// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The one interface every haptic device implements (Novint Falcon over libusb, the simulated
// Falcon, scripted trajectory, host-driven, null). Positions and velocities are in the device's
// own workspace frame, SI units (m, m/s, N); the haptic loop maps that workspace onto the fluid
// domain. A device is used by one thread at a time: the haptic loop calls read() then
// writeForce() once per period (1 kHz), and neither may block for longer than about a period.
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace hf::haptics {

struct DeviceInfo {
  std::string name;                       // e.g. "Novint Falcon", "scripted", "null"
  std::string kind;                       // "falcon", "simulated_falcon", "scripted", "host", "null"
  std::string serial;                     // empty when the device has none
  glm::vec3 workspace_min_m{-0.05f};      // reachable box, device frame, m
  glm::vec3 workspace_max_m{0.05f};
  float max_force_n = 0.0f;               // the safety stage never commands more than this
  // Rendering limits (0: not reported, as for the virtual devices): the largest stiffness and
  // damping the device renders stably at its loop rate. They bound the session's default
  // force gain (rendering_limits.h) and the passivity controller's damper.
  float max_stiffness_n_m = 0.0f;         // N/m
  float max_damping_n_s_m = 0.0f;         // N s/m
  // The spread of a position reading's quantization error per axis, m (0: exact or not reported):
  // the grip's velocity (grip_motion.h) fits its readings within it.
  float position_resolution_m = 0.0f;
};

struct DeviceState {
  glm::vec3 position_m{0.0f};             // end effector, device frame
  glm::vec3 velocity_m_s{0.0f};           // estimated by the device or its driver
  std::uint32_t buttons = 0;              // bit i = button i pressed
  bool homed = false;                     // false: no force may be commanded yet
  double time_s = 0.0;                    // steady-clock time of the reading
  // A 6-DoF pose (the host device fed a Blender object's rotation); the Falcon has none (3-DoF).
  bool has_orientation = false;
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // unit quaternion (w, x, y, z), device frame
  glm::vec3 angular_velocity_rad_s{0.0f};         // device frame, rad/s
};

class Device {
 public:
  virtual ~Device() = default;
  virtual DeviceInfo info() const = 0;
  // Latest state. Throws hf::Error (naming the device and what failed) if the device is gone;
  // after that the device is unusable and writeForce() does nothing.
  virtual DeviceState read() = 0;
  // Commands a force (N, device frame). The caller has already applied safety limits; a device
  // still never exceeds info().max_force_n.
  virtual void writeForce(const glm::vec3& force_n) = 0;
  // Zero force, on the hardware before this returns: the haptic loop's last command when it
  // stops or fails. A device whose writeForce() only takes effect with its next read() (the
  // Falcon) sends the zero here, or the last force would stay on. Never throws.
  virtual void zeroForce() noexcept {
    try {
      writeForce(glm::vec3(0.0f));
    } catch (...) {  // the device is gone: nothing more can be commanded
    }
  }
  // Zero force, release the hardware. Idempotent; never throws.
  virtual void close() = 0;

  // One driver at a time (see DeviceClaim): a haptic loop holds the device while it runs, a
  // host's own read()/writeForce() call for its length. False: someone else holds it.
  bool tryClaim() noexcept {
    bool free = false;
    return claimed_.compare_exchange_strong(free, true, std::memory_order_acq_rel);
  }
  void releaseClaim() noexcept { claimed_.store(false, std::memory_order_release); }
  bool claimed() const noexcept { return claimed_.load(std::memory_order_acquire); }

 private:
  std::atomic<bool> claimed_{false};
};

// Python holds devices through this holder type (bindings use py::class_<Device, DevicePtr>).
using DevicePtr = std::shared_ptr<Device>;

}  // namespace hf::haptics
