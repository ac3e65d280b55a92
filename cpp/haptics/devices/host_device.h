// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// HostDevice: the handle's pose is pushed by the host (a Blender object, the mouse, a script),
// typically once per frame at 24-60 Hz. The velocity is the finite difference of the two latest
// pushes (their own time stamps); read() extrapolates the position along it for at most one push
// interval, so the 1 kHz loop sees a smooth path and a stalled host holds still.
// A push may carry an orientation (a unit quaternion: the object's rotation): the device is then
// 6-DoF (DeviceState::has_orientation), its angular velocity the rotation between the two latest
// pushes over their time (shortest arc), and read() turns it along that for as long as it moves
// the position.
// pushPose() may be called from any thread (pushers take turns under a mutex); read(), on the
// haptic thread, takes no lock: the latest push comes through a Mailbox.
#include <atomic>
#include <cstdint>
#include <mutex>

#include "haptics/devices/device.h"
#include "haptics/handoff/mailbox.h"

namespace hf::haptics {

class HostDevice : public Device {
 public:
  // Largest |coordinate| of a pushed position, m (a scene's object, not a number that overflows
  // the velocity or the workspace map).
  static constexpr float kMaxPositionM = 1e6f;

  // extrapolate: move the pose along the estimated velocity between pushes.
  explicit HostDevice(float max_force_n = 10.0f, bool extrapolate = true);

  DeviceInfo info() const override { return info_; }
  DeviceState read() override;  // not homed until the first push; throws after close()
  void writeForce(const glm::vec3& force_n) override;
  void close() override { closed_ = true; }

  // position_m: device frame (m). time_s: when the pose was sampled, on any clock that runs in
  // seconds (time.monotonic() by default); it must increase from push to push.
  // Throws InvalidArgument for a non-finite value, a coordinate beyond kMaxPositionM or a time
  // that does not increase.
  void pushPose(const glm::vec3& position_m, double time_s);
  void pushPose(const glm::vec3& position_m);  // sampled now (monotonic clock)
  // With an orientation (w, x, y, z; normalised here): finite and not zero, else InvalidArgument.
  void pushPose(const glm::vec3& position_m, const glm::quat& orientation, double time_s);
  void pushPose(const glm::vec3& position_m, const glm::quat& orientation);
  std::uint64_t pushes() const { return latest_.version(); }
  glm::vec3 lastForce() const;

  // The state `elapsed_s` seconds after the latest push arrived (read() uses the clock); the
  // extrapolation stops after one push interval (at most 0.1 s). NaN throws InvalidArgument.
  DeviceState stateAfter(double elapsed_s) const;

 private:
  struct Push;
  DeviceState stateFrom(const Push& p, double elapsed_s) const;
  void push(const glm::vec3& position_m, const glm::quat* orientation, double time_s);

  struct Push {
    bool valid = false;
    glm::vec3 position_m{0.0f};
    glm::vec3 velocity_m_s{0.0f};
    bool has_orientation = false;
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 angular_velocity_rad_s{0.0f};
    double time_s = 0.0;        // the caller's time stamp
    double arrival_s = 0.0;     // monotonic clock when it arrived
    double interval_s = 0.0;    // since the push before (0 for the first)
  };

  DeviceInfo info_;
  bool extrapolate_;
  std::mutex push_mutex_;  // pushers only; the haptic thread never takes it
  Push previous_;          // guarded by push_mutex_
  Mailbox<Push> latest_;
  Mailbox<glm::vec3> last_force_;
  std::atomic<bool> closed_{false};
  Push cached_;  // read() only: the last push it saw, kept if a read overlaps a push
};

}  // namespace hf::haptics
