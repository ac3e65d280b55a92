// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PlaybackGuide: haptic playback of an existing motion (the keys the timeline plays), at the
// haptic rate. A spring-damper pulls the grip towards the played pose, with the played velocity
// fed forward (a PD guide on the error to a moving target, as in haptic guidance / "record and
// play" training: Feygin, Keehner and Tendick 2002; the passive-guidance family of Rosenberg's
// virtual fixtures): device frame, per axis,
//   F = w * clampMagnitude(K (x_t - x_h) + B (v_t - v_h), max_force)
// x_t, v_t: the played pose carried forward at its velocity since the host set it (at most
// stale_s; older, the guide lets go), x_h, v_h: the grip. Seen from the target, the guide is a
// spring-damper, passive when its gains are inside the device's stable limits (Colgate and
// Schenkel: b > K T / 2 for a sampled spring; the haptic loop keeps K and B, together with the
// virtual coupling's, within DeviceInfo's max_stiffness and max_damping). The hand can resist:
// the force is capped at max_force (a share of the session's max force), so the fluid's force
// keeps room. w (0..1) ramps in over ramp_s when a target arrives and out over ramp_s when it is
// released or stale, so neither engaging nor letting go is a step in force; the haptic loop uses
// the same w to hand the fluid's probe over between the grip and the played pose.
#include <glm/glm.hpp>

namespace hf::haptics {

// The guide's gains and force bound when the settings leave them at 0: shares of the device's
// maximum stable stiffness and damping (the Falcon: 750 N/m, 5 N s/m) and of the session's
// max_force (the Falcon: 4 N of 8). With the coupling's own shares (1/4, 1/2) the hand touches at
// most 1/2 of the device's stiffness and 3/4 of its damping; a resting 300 N/m hand ends 29% of
// its offset from the played pose, a relaxed one (5 N/m) within 1%.
inline constexpr float kGuideStiffnessShare = 0.25f;
inline constexpr float kGuideDampingShare = 0.25f;
inline constexpr float kGuideForceShare = 0.5f;

struct GuideSettings {
  float stiffness_n_m = 0.0f;  // K (N/m, >= 0); 0: kGuideStiffnessShare x the device's maximum
  float damping_n_s_m = 0.0f;  // B (N s/m, >= 0); 0: kGuideDampingShare x the device's maximum
  float max_force_n = 0.0f;    // |F| bound (N, >= 0); 0: kGuideForceShare x the session's max_force
  double ramp_s = 0.25;        // fade in and out (s, 0.01 .. 5)
  // A target older than this (s, 0.05 .. 10) is let go: the host stopped feeding it (Blender's
  // ticks come as often as its window redraws; under load that can be 1-3 a second).
  double stale_s = 1.0;
  void validate() const;  // throws InvalidArgument naming the bad setting
};

// The pose the timeline plays, from the host (a Mailbox payload: trivially copyable). Domain
// frame when the host sets it, device frame once the haptic loop has mapped it.
struct GuideTarget {
  bool active = false;
  glm::vec3 position_m{0.0f};
  glm::vec3 velocity_m_s{0.0f};
  double time_s = 0.0;  // monotonicNowS() when the host set it
};

// The played position now: the target carried forward at its velocity since it was set, for at
// most stale_s (after that the guide lets go), in the target's own frame.
glm::vec3 carriedForward(const GuideTarget& target, double now_s, double stale_s);

struct GuideTick {
  glm::vec3 force_n{0.0f};   // on the hand, device N
  glm::vec3 target_m{0.0f};  // the played pose now (carried forward), device frame
  glm::vec3 target_m_s{0.0f};
  float weight = 0.0f;       // 0: off, 1: fully engaged
};

class PlaybackGuide {
 public:
  explicit PlaybackGuide(const GuideSettings& s);  // gains as given (the loop resolves the zeros)
  // One haptic period: the target (device frame), the grip's position and velocity, now and dt.
  GuideTick step(const GuideTarget& target, const glm::vec3& hand_m, const glm::vec3& hand_m_s, double now_s,
                 double dt_s);
  float weight() const { return weight_; }
  void reset();
  const GuideSettings& settings() const { return s_; }

 private:
  GuideSettings s_;
  float weight_ = 0.0f;
  GuideTarget last_{};  // the target while fading out after a release
};

}  // namespace hf::haptics
