// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ScriptedDevice: a handle that follows timed waypoints (device frame, m), linearly interpolated,
// with the segment's slope as its velocity. Time starts at the first read(). At the end it
// holds the last waypoint (velocity 0) or loops back to the first one. Always homed; forces are
// accepted and kept (lastForce()) so tests and traces can see what the loop commanded.
#include <atomic>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "haptics/devices/device.h"
#include "haptics/handoff/mailbox.h"

namespace hf::haptics {

class ScriptedDevice : public Device {
 public:
  static constexpr std::size_t kMaxCsvLineChars = 4096;

  // times_s strictly increasing and finite (at least one); positions_m finite, one per time;
  // consecutive waypoints far enough apart in time for a finite velocity. loop needs at least
  // two waypoints. Throws InvalidArgument naming the bad entry.
  ScriptedDevice(std::vector<double> times_s, std::vector<glm::vec3> positions_m, bool loop,
                 float max_force_n = 10.0f);
  // Reads "t,x,y,z" rows (s, m); blank lines, '#' comments and one header line are skipped.
  // A regular file only (not a folder or a device), lines of at most kMaxCsvLineChars.
  static std::shared_ptr<ScriptedDevice> fromCsv(const std::string& path, bool loop, float max_force_n = 10.0f);

  DeviceInfo info() const override { return info_; }
  DeviceState read() override;
  void writeForce(const glm::vec3& force_n) override;
  void close() override { closed_ = true; }

  // The state t_s seconds after the script started (pure; read() uses it with the clock).
  // t_s < 0 is the start; NaN or infinite t_s throws InvalidArgument.
  DeviceState stateAt(double t_s) const;
  double durationS() const { return times_.back() - times_.front(); }
  bool loops() const { return loop_; }
  glm::vec3 lastForce() const;

 private:
  glm::vec3 segmentVelocity(std::size_t i) const;  // waypoint i to i + 1, m/s

  std::vector<double> times_;
  std::vector<glm::vec3> positions_;
  bool loop_;
  DeviceInfo info_;
  double start_s_ = -1.0;  // clock time of the first read (read() runs on one thread)
  std::atomic<bool> closed_{false};
  Mailbox<glm::vec3> last_force_;
};

}  // namespace hf::haptics
