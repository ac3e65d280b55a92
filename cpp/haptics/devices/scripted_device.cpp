// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/devices/scripted_device.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/finite.h"
#include "haptics/devices/device_checks.h"
#include "haptics/handoff/clock.h"

namespace hf::haptics {

ScriptedDevice::ScriptedDevice(std::vector<double> times_s, std::vector<glm::vec3> positions_m, bool loop,
                               float max_force_n)
    : times_(std::move(times_s)), positions_(std::move(positions_m)), loop_(loop) {
  checkMaxForce(max_force_n, "scripted device");
  if (times_.empty()) throw InvalidArgument("scripted device: give at least one waypoint (time, position)");
  if (times_.size() != positions_.size()) {
    throw InvalidArgument("scripted device: " + std::to_string(times_.size()) + " times but " +
                          std::to_string(positions_.size()) + " positions; give one position (x, y, z) per time");
  }
  for (std::size_t i = 0; i < times_.size(); ++i) {
    const glm::vec3& p = positions_[i];
    if (!std::isfinite(times_[i]) || !allFinite(p)) {
      throw InvalidArgument("scripted device: waypoint " + std::to_string(i) + " is not finite");
    }
    if (i > 0 && !(times_[i] > times_[i - 1])) {
      throw InvalidArgument("scripted device: times must increase strictly; waypoint " + std::to_string(i) + " at " +
                            std::to_string(times_[i]) + " s follows " + std::to_string(times_[i - 1]) + " s");
    }
    // Waypoints 1e-300 s apart (or 1 m in 1e-40 s) give an infinite or NaN velocity.
    if (i > 0 && !allFinite(segmentVelocity(i - 1))) {
      throw InvalidArgument("scripted device: waypoints " + std::to_string(i - 1) + " and " + std::to_string(i) +
                            " (" + std::to_string(times_[i - 1]) + " s, " + std::to_string(times_[i]) +
                            " s) are too close in time for a finite velocity; space them further apart");
    }
  }
  if (durationS() > 0.0 && !std::isfinite(durationS())) {
    throw InvalidArgument("scripted device: the script lasts longer than a double can hold; give times (s) that "
                          "span a finite duration");
  }
  if (loop_ && times_.size() < 2) throw InvalidArgument("scripted device: a looping script needs at least two waypoints");
  info_.name = "scripted";
  info_.kind = "scripted";
  info_.max_force_n = max_force_n;
  info_.workspace_min_m = info_.workspace_max_m = positions_.front();
  for (const auto& p : positions_) {
    info_.workspace_min_m = glm::min(info_.workspace_min_m, p);
    info_.workspace_max_m = glm::max(info_.workspace_max_m, p);
  }
  last_force_.write(glm::vec3(0.0f));
}

std::shared_ptr<ScriptedDevice> ScriptedDevice::fromCsv(const std::string& path, bool loop, float max_force_n) {
  // A folder "opens" and reads as empty, /dev/zero reads until memory runs out: regular files only.
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) {
    throw InvalidArgument("scripted device: '" + path + "' is " +
                          (std::filesystem::is_directory(st) ? "a folder" : "not a regular file") +
                          "; give a CSV file of t,x,y,z rows (s, m)");
  }
  std::ifstream in(path);
  if (!in) throw InvalidArgument("scripted device: cannot open '" + path + "'; give a CSV file of t,x,y,z rows (s, m)");
  std::vector<double> times;
  std::vector<glm::vec3> positions;
  std::string line;
  int number = 0;
  bool header_seen = false;
  // One line at a time, at most kMaxCsvLineChars (a t,x,y,z row is a few dozen characters).
  const auto nextLine = [&]() {
    line.clear();
    for (int c = in.get(); c != std::char_traits<char>::eof(); c = in.get()) {
      if (c == '\n') return true;
      if (line.size() >= kMaxCsvLineChars) {
        throw InvalidArgument("scripted device: " + path + ":" + std::to_string(number + 1) + " is longer than " +
                              std::to_string(kMaxCsvLineChars) + " characters; give a CSV file of t,x,y,z rows (s, m)");
      }
      line.push_back(static_cast<char>(c));
    }
    return !line.empty();
  };
  while (nextLine()) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double v[4];
    int got = 0;
    while (got < 4 && (row >> v[got])) ++got;
    std::string rest;
    const bool extra = static_cast<bool>(row >> rest);
    if (got == 0 && times.empty() && !header_seen) {
      header_seen = true;  // a header line such as "t,x,y,z"
      continue;
    }
    if (got != 4 || extra) {
      throw InvalidArgument("scripted device: " + path + ":" + std::to_string(number) +
                            ": expected four numbers t,x,y,z (s, m), got '" + line + "'");
    }
    times.push_back(v[0]);
    positions.emplace_back(static_cast<float>(v[1]), static_cast<float>(v[2]), static_cast<float>(v[3]));
  }
  if (times.empty()) throw InvalidArgument("scripted device: " + path + " holds no t,x,y,z rows");
  try {
    return std::make_shared<ScriptedDevice>(std::move(times), std::move(positions), loop, max_force_n);
  } catch (const InvalidArgument& e) {  // the waypoints' own checks (order, spacing): name the file
    throw InvalidArgument(path + ": " + e.what());
  }
}

glm::vec3 ScriptedDevice::segmentVelocity(std::size_t i) const {
  // In double: the float of a tiny span is 0.
  const glm::dvec3 step = glm::dvec3(positions_[i + 1]) - glm::dvec3(positions_[i]);
  return glm::vec3(step / (times_[i + 1] - times_[i]));
}

DeviceState ScriptedDevice::stateAt(double t_s) const {
  if (std::isnan(t_s) || std::isinf(t_s)) {
    throw InvalidArgument("scripted device: state_at needs a finite time since the start (s), got " +
                          std::to_string(t_s));
  }
  DeviceState s;
  s.homed = true;
  if (times_.size() == 1) {
    s.position_m = positions_.front();
    return s;
  }
  double t = times_.front() + std::max(0.0, t_s);
  if (loop_) {
    t = times_.front() + std::fmod(t - times_.front(), durationS());
  } else if (t >= times_.back()) {
    s.position_m = positions_.back();
    return s;
  }
  // Segment [i, i + 1] with times_[i] <= t < times_[i + 1]. A looped time can round up onto the
  // last waypoint (fmod leaves just under the duration, adding the start rounds it up): that
  // is the end of the last segment, never a segment starting at the last waypoint.
  const auto above = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), t) - times_.begin());
  const std::size_t i = std::min(std::max<std::size_t>(above, 1), times_.size() - 1) - 1;
  const double span = times_[i + 1] - times_[i];
  const float a = static_cast<float>(std::clamp((t - times_[i]) / span, 0.0, 1.0));
  s.position_m = positions_[i] + a * (positions_[i + 1] - positions_[i]);
  s.velocity_m_s = segmentVelocity(i);
  return s;
}

DeviceState ScriptedDevice::read() {
  if (closed_) throw Error("scripted device: read after close(); make a new device");
  const double now = monotonicNowS();
  if (start_s_ < 0.0) start_s_ = now;
  DeviceState s = stateAt(now - start_s_);
  s.time_s = now;
  return s;
}

void ScriptedDevice::writeForce(const glm::vec3& force_n) {
  if (closed_) return;
  last_force_.write(force_n);
}

glm::vec3 ScriptedDevice::lastForce() const {
  glm::vec3 f(0.0f);
  last_force_.tryRead(f);
  return f;
}

}  // namespace hf::haptics
