// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// What the haptic thread and the simulation thread hand each other through Mailboxes.
// Both are in the fluid domain's frame (m, m/s, fluid N); times are monotonicNowS().
#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace hf::haptics {

struct PoseFrame {           // haptic thread -> simulation thread, every haptic period
  glm::vec3 position_m{0.0f};
  glm::vec3 velocity_m_s{0.0f};
  double time_s = 0.0;       // when the device was read
  bool homed = false;
  bool has_orientation = false;                   // the device reports one (6-DoF)
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // the probe's world rotation (unit quaternion)
  glm::vec3 angular_velocity_rad_s{0.0f};         // world frame, rad/s
};

struct ForceFrame {          // simulation thread -> haptic thread, every simulation step
  glm::vec3 force_n{0.0f};             // fluid force on the probe
  glm::vec3 probe_velocity_m_s{0.0f};  // the probe velocity the step used (prediction's v0)
  double pose_time_s = 0.0;            // time of the pose the step used (latency)
  double publish_time_s = 0.0;         // when the force was published (age)
  double sim_rate_hz = 0.0;            // measured simulation rate (filter bandwidth)
  double step_dt_s = 0.0;              // the step's own time step, s (0: unknown)
};

}  // namespace hf::haptics
