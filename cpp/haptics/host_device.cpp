#include "haptics/host_device.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"
#include "haptics/clock.h"
#include "haptics/device_checks.h"

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

void HostDevice::pushPose(const glm::vec3& position_m) { pushPose(position_m, monotonicNowS()); }

void HostDevice::pushPose(const glm::vec3& position_m, double time_s) {
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
