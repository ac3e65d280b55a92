// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/devices/host_device.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"
#include "haptics/devices/device_checks.h"
#include "haptics/handoff/clock.h"

namespace hf::haptics {

namespace {
// Longest stretch the pose is carried along its velocity after a push, s.
constexpr double kMaxExtrapolationS = 0.1;
}  // namespace

HostDevice::HostDevice(float max_force_n, bool extrapolate) : extrapolate_(extrapolate) {
  checkMaxForce(max_force_n, "host device");
  info_.name = "host-driven";
  info_.kind = "host";
  info_.max_force_n = max_force_n;
  last_force_.write(glm::vec3(0.0f));
}

void HostDevice::pushPose(const glm::vec3& position_m) { push(position_m, nullptr, monotonicNowS()); }

void HostDevice::pushPose(const glm::vec3& position_m, double time_s) { push(position_m, nullptr, time_s); }

void HostDevice::pushPose(const glm::vec3& position_m, const glm::quat& orientation) {
  push(position_m, &orientation, monotonicNowS());
}

void HostDevice::pushPose(const glm::vec3& position_m, const glm::quat& orientation, double time_s) {
  push(position_m, &orientation, time_s);
}

void HostDevice::push(const glm::vec3& position_m, const glm::quat* orientation, double time_s) {
  glm::quat unit(1.0f, 0.0f, 0.0f, 0.0f);
  if (orientation) {
    const glm::dquat q(*orientation);
    const double norm = glm::length(q);
    if (!std::isfinite(norm) || !(norm > 1e-6)) {
      throw InvalidArgument("host device: push_pose orientation must be a finite, nonzero quaternion (w, x, y, z), got (" +
                            std::to_string(q.w) + ", " + std::to_string(q.x) + ", " + std::to_string(q.y) + ", " +
                            std::to_string(q.z) + ")");
    }
    unit = glm::quat(q / norm);
  }
  if (!allFinite(position_m) || !std::isfinite(time_s)) {
    throw InvalidArgument("host device: push_pose needs a finite position (m) and time (s)");
  }
  if (glm::any(glm::greaterThan(glm::abs(position_m), glm::vec3(kMaxPositionM)))) {
    throw InvalidArgument("host device: push_pose position (" + std::to_string(position_m.x) + ", " +
                          std::to_string(position_m.y) + ", " + std::to_string(position_m.z) +
                          ") m is beyond " + std::to_string(kMaxPositionM) + " m; push positions in metres");
  }
  std::lock_guard<std::mutex> lock(push_mutex_);
  Push next;
  next.valid = true;
  next.position_m = position_m;
  next.time_s = time_s;
  next.arrival_s = monotonicNowS();
  if (latest_.version() > 0) {
    const double dt = time_s - previous_.time_s;
    if (!(dt > 0.0)) {
      throw InvalidArgument("host device: push_pose times must increase; got " + std::to_string(time_s) +
                            " s after " + std::to_string(previous_.time_s) + " s");
    }
    // In double: a tiny dt (the float of 1e-300 is 0) must not give an infinite velocity, which
    // read() would turn into a NaN position.
    const glm::dvec3 velocity = glm::dvec3(position_m - previous_.position_m) / dt;
    next.velocity_m_s = glm::vec3(velocity);
    if (!allFinite(next.velocity_m_s)) {
      throw InvalidArgument("host device: push_pose times " + std::to_string(previous_.time_s) + " s and " +
                            std::to_string(time_s) + " s are too close for a finite velocity; push poses at "
                            "their own sample times (s), at least a microsecond apart");
    }
    next.interval_s = dt;
    if (orientation && previous_.has_orientation) {
      // The rotation from the previous push to this one, shortest arc, as an angular velocity
      // (world frame): axis * angle / dt.
      glm::dquat d = glm::dquat(unit) * glm::conjugate(glm::dquat(previous_.orientation));
      if (d.w < 0.0) d = -d;
      const glm::dvec3 axis(d.x, d.y, d.z);
      const double s = glm::length(axis);
      if (s > 0.0) {
        const double angle = 2.0 * std::atan2(s, d.w);
        next.angular_velocity_rad_s = glm::vec3(axis * (angle / (s * dt)));
        if (!allFinite(next.angular_velocity_rad_s)) {
          throw InvalidArgument("host device: push_pose times " + std::to_string(previous_.time_s) + " s and " +
                                std::to_string(time_s) + " s are too close for a finite angular velocity; push "
                                "poses at their own sample times (s), at least a microsecond apart");
        }
      }
    }
  }
  if (orientation) {
    next.has_orientation = true;
    next.orientation = unit;
  }
  previous_ = next;
  latest_.write(next);
}

DeviceState HostDevice::stateAfter(double elapsed_s) const {
  if (std::isnan(elapsed_s)) {
    throw InvalidArgument("host device: state_after needs a number of seconds since the latest push, got NaN");
  }
  Push p;
  if (!latest_.tryRead(p)) return DeviceState{};  // nothing pushed yet: not homed, no force
  return stateFrom(p, elapsed_s);
}

DeviceState HostDevice::stateFrom(const Push& p, double elapsed_s) const {
  DeviceState s;
  if (!p.valid) return s;
  s.homed = true;
  s.velocity_m_s = p.velocity_m_s;
  const double ahead = extrapolate_ ? std::clamp(elapsed_s, 0.0, std::min(p.interval_s, kMaxExtrapolationS)) : 0.0;
  s.position_m = p.position_m + p.velocity_m_s * static_cast<float>(ahead);
  if (p.has_orientation) {
    s.has_orientation = true;
    s.angular_velocity_rad_s = p.angular_velocity_rad_s;
    s.orientation = p.orientation;
    const float spin = glm::length(p.angular_velocity_rad_s);
    if (ahead > 0.0 && spin > 0.0) {
      s.orientation = glm::normalize(glm::angleAxis(spin * static_cast<float>(ahead), p.angular_velocity_rad_s / spin) *
                                     p.orientation);
    }
  }
  return s;
}

DeviceState HostDevice::read() {
  if (closed_) throw Error("host device: read after close(); make a new device");
  const double now = monotonicNowS();
  latest_.tryRead(cached_);  // on a (rare) overlap with a push, the previous push stands
  DeviceState s = stateFrom(cached_, now - cached_.arrival_s);
  s.time_s = now;
  return s;
}

void HostDevice::writeForce(const glm::vec3& force_n) {
  if (closed_) return;
  last_force_.write(force_n);
}

glm::vec3 HostDevice::lastForce() const {
  glm::vec3 f(0.0f);
  last_force_.tryRead(f);
  return f;
}

}  // namespace hf::haptics
