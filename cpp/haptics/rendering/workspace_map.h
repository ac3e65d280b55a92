// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// WorkspaceMap: the device's workspace onto the fluid domain, and the fluid's force back.
//   domain position = offset + scale * device position     (per axis; a negative scale flips it)
//   domain velocity = scale * device velocity          (positionToDevice, velocityToDevice: the inverse)
//   device force    = force_gain * sign(scale) * fluid force (device N per fluid N)
//   domain axes     = sign(scale) * device force (forceToDomainAxes: the same newtons, the
//                     mirror undone; the direction the fluid's force had)
//   domain rotation = S R S with S = diag(sign(scale)) (a rotation: the map's mirror on both
//                     sides; scale's size does not turn anything), angular velocity det(S) S w
// The force keeps its direction in the user's hand: an axis the map flips is flipped back.
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace hf::haptics {

struct WorkspaceMap {
  glm::vec3 scale{1.0f};        // domain m per device m, per axis, nonzero
  glm::vec3 offset_m{0.0f};     // domain position of the device origin, m
  float force_gain = 1.0f;      // device N per fluid N, >= 0

  void validate() const;        // throws InvalidArgument naming the bad value
  glm::vec3 positionToDomain(const glm::vec3& p) const { return offset_m + scale * p; }
  glm::vec3 velocityToDomain(const glm::vec3& v) const { return scale * v; }
  glm::vec3 positionToDevice(const glm::vec3& p) const { return (p - offset_m) / scale; }  // the inverse
  glm::vec3 velocityToDevice(const glm::vec3& v) const { return v / scale; }
  glm::vec3 forceToDevice(const glm::vec3& f) const { return force_gain * glm::sign(scale) * f; }
  glm::vec3 forceToDomainAxes(const glm::vec3& device_n) const { return glm::sign(scale) * device_n; }
  glm::quat orientationToDomain(const glm::quat& q) const {
    const glm::vec3 s = glm::sign(scale);
    // S R S for a diagonal S of signs: the quaternion's vector part picks up det(S) S.
    const float det = s.x * s.y * s.z;
    return glm::quat(q.w, det * s.x * q.x, det * s.y * q.y, det * s.z * q.z);
  }
  glm::vec3 angularVelocityToDomain(const glm::vec3& w) const {
    const glm::vec3 s = glm::sign(scale);
    return (s.x * s.y * s.z) * s * w;
  }
};

}  // namespace hf::haptics
