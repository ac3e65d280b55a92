// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// ForcePipeline: one haptic period's force computation, free of threads and clocks so it can be
// tested sample by sample:
//   latest simulation force (fluid N) -> [prediction F0 + B (v - v0)] -> low-pass (cutoff from
//   the simulation rate) -> workspace map (gain, axis signs) -> passivity controller (a damper that
//   removes any energy the loop made, see passivity_controller.h) -> safety (the last word on
//   |F|: clamp, slew) -> commanded device force.
// With the virtual coupling active (coupling.active(), the default on a device that reports its
// rendering limits) the force is rendered at the haptic rate instead: each new step identifies
// the local model (fluid_model.h: added mass, drag, steady part); the steady part is low-passed
// and mapped; a proxy carrying the model's mass and drag (scaled by gain x |scale|) is coupled to
// the hand (virtual_coupling.h) -> passivity controller -> safety as above.
// Haptic playback: with a played pose in TickInput::guide, the guide's spring-damper
// (playback_guide.h) is added after the passivity controller and before safety (clamp, slew): it
// moves the hand on purpose, so the controller, which keeps the fluid's rendering passive, does not
// count its work (the observer sees the held force less the guide's part). While the guide is
// engaged the fluid's probe moves along the played pose, not with the hand: the hand gets the
// rendering's steady part on the played probe (at most kPlayedForceShare of the guide's force)
// blended in by the guide's weight, the coupling's proxy is held at the hand and the passivity
// controller rests (reset).
// tick() runs these as named stages (the private methods below, force_pipeline.cpp), after deciding
// the period's mode once (decide()).
#include <cstdint>

#include "haptics/devices/device.h"
#include "haptics/handoff/frames.h"
#include "haptics/rendering/drag_predictor.h"
#include "haptics/rendering/fluid_model.h"
#include "haptics/rendering/force_safety.h"
#include "haptics/rendering/grip_motion.h"
#include "haptics/rendering/low_pass_filter.h"
#include "haptics/rendering/passivity_controller.h"
#include "haptics/rendering/playback_guide.h"
#include "haptics/rendering/virtual_coupling.h"
#include "haptics/rendering/workspace_map.h"

namespace hf::haptics {

// With the coupling, the steady part's low-pass cutoff is this share of the filter's (0.1 x the
// simulation rate by default): on the simulated Falcon (20^3 water, gain 0.08, resting hand, 5 s)
// it brought the energy into the hand from 3.2-4.7 mJ down to 1.5-1.6 mJ.
inline constexpr double kSteadyBandwidthShare = 0.2;

// With the coupling, the passivity controller does not act below this grip speed (m/s), whatever
// its own dead-band, held against the fitted speed (grip_motion.h): the 4-period velocity its
// damper acts on jitters by one encoder count over its span, 0.04 mm / 4 ms = 10 mm/s on the
// Falcon (in a slow push too, without the fitted speed as the gate), and a controller damping that jitter at rest fed
// the hand through the coupling (simulated Falcon, air strokes at the derived gain: 1.0-2.3 mJ into
// the hand, almost all at rest; 0.01-0.18 mJ with 15 mm/s; 0.13-0.45 mJ with no controller).
inline constexpr float kCoupledDeadbandM_s = 0.015f;

// While the playback guide is engaged, the fluid's force the hand gets (the rendering's steady part
// on the played probe) is at most this share of the guide's force bound: the guide keeps leading,
// and a relaxed hand ends at most share x guide_max_force / guide_stiffness off the played pose for
// it, which is the jump at the hand-over (Record). At the amplified gain the fluid's force on a
// probe moved along a path is several newtons (air, 0.08 m sphere, gain 62: 0.3 N x 62); a share of
// 0.25 (0.5 N at Max Force 4 N) held a relaxed grip 0.67 mm (device) = 8 mm (world, scale 12.5)
// off the keys, 0.1 (0.2 N) about 0.3 mm = 3-4 mm.
inline constexpr float kPlayedForceShare = 0.1f;

// While the coupled rendering ramps in, the hand gets the steady part alone, a held force with no
// impedance behind it. At rest that is buoyancy and the flow's push, and their work on a hand that
// yields to them is the fluid's. But a hand that moves as force starts (the session started mid-
// motion, the device still settling from homing) gives the model's first, impulsive steps, whose
// residual is the model's error and can point along the motion: water at 16^3, a hand falling at
// 0.17 m/s as the first step landed, got -0.7..-1.3 N along its motion and 1.5-2.0 mJ. So above the
// coupled dead-band speed the held force keeps only what resists the grip's motion (its component
// along the velocity, when that would push the hand on, is taken out); below it, untouched.
glm::vec3 rampHeldForce(const glm::vec3& steady_n, const glm::vec3& grip_m_s);

struct PipelineSettings {
  WorkspaceMap map;
  LowPassSettings filter;
  bool prediction = false;
  PassivitySettings passivity;
  SafetySettings safety;
  CouplingSettings coupling;
  GuideSettings guide;  // haptic playback (playback_guide.h); its gains resolved by the loop
  // The device's position resolution (DeviceInfo::position_resolution_m, m, >= 0), filled in by the
  // haptic loop: the grip's velocity fits the readings within it (grip_motion.h).
  double position_resolution_m = 0.0;
  void validate() const;
};

struct TickInput {
  double now_s = 0.0;
  double dt_s = 0.001;            // period since the last tick, s
  DeviceState state;              // this period's device reading
  bool have_force = false;        // a ForceFrame has arrived (force is valid)
  bool new_frame = false;         // force is a frame not seen before
  ForceFrame force;
  bool enabled = true;            // false: paused, failed or stopping -> zero
  GuideTarget guide;              // the played pose (device frame); inactive: no guide
};

struct TickOutput {
  glm::vec3 grip_m{0.0f};             // the grip's position this period's forces came from, device frame
  glm::vec3 sim_force_n{0.0f};        // latest simulation force, fluid N
  glm::vec3 predicted_n{0.0f};        // after prediction (= sim force without it; the local
                                      // model's steady part with the coupling), fluid N
  glm::vec3 filtered_n{0.0f};         // low-passed and mapped, device N
  glm::vec3 passive_n{0.0f};          // after the passivity controller, device N
  double damping_n_s_m = 0.0;         // the passivity controller's damping this period, N s/m
  glm::vec3 commanded_n{0.0f};        // after safety, device N
  glm::vec3 commanded_domain_n{0.0f}; // commanded_n in the domain's axes (map.forceToDomainAxes), device N
  double cutoff_hz = 0.0;
  double force_age_s = 0.0;
  double stale_after_s = 0.0;         // the age at which this force starts fading (staleAfterS), s
  bool coupled = false;               // rendered through the virtual coupling
  // The grip's velocity the simulation's probe is given, device frame, m/s: fitted within the
  // device's position resolution (grip_motion.h, the coupling damper's velocity) where the device
  // reports one and the reading is finite; else the device's own estimate (a host device's is the
  // slope between its pushes, which a finite difference of its extrapolated readings would turn
  // into spikes at each push). Not the Falcon driver's low-passed estimate: a step takes the
  // probe's acceleration from the change of this velocity over its own time step, and that
  // estimate's jitter (0.007-0.010 m/s rms of probe velocity in the seed's push at scale 12.5,
  // against 0.005-0.006 fitted) was a noise of a quarter of the push's acceleration in each 0.5 s
  // step, with the fluid's added-mass reaction to it (test_haptic_seed_feel.py).
  glm::vec3 grip_velocity_m_s{0.0f};
  glm::vec3 proxy_m{0.0f};            // the coupling's proxy, device frame, m (coupled only)
  glm::vec3 drag_n_s_m{0.0f};         // the local model's drag, fluid N s/m (<= 0; coupled only)
  // Haptic playback (playback_guide.h): the guide's force (device N, in passive_n and so in
  // commanded_n; added after the passivity controller, which balances the fluid's rendering only),
  // its weight (0 off .. 1 engaged) and the played pose now (device frame).
  glm::vec3 guide_n{0.0f};
  float guide_weight = 0.0f;
  glm::vec3 guide_target_m{0.0f};
  glm::vec3 guide_target_m_s{0.0f};
};

class ForcePipeline {
 public:
  explicit ForcePipeline(const PipelineSettings& s);
  TickOutput tick(const TickInput& in);
  void reset();
  const PipelineSettings& settings() const { return s_; }
  const ForceSafety& safety() const { return safety_; }
  const DragPredictor& predictor() const { return predictor_; }
  const PassivityController& passivity() const { return passivity_; }
  const FluidModel& model() const { return model_; }
  const VirtualCoupling& coupling() const { return coupling_; }
  const PlaybackGuide& guide() const { return guide_; }

 private:
  // What renders this period, decided once at its start (decide()): an engaged guide first, then
  // with the coupling the safety stage's ramp-in. Whether the output is off is decided beside it
  // (Period::output_off), not as a mode: an output that is off renders as its mode says (the
  // proxy and the filters keep their course for the next period) but commands nothing.
  enum class TickMode {
    Direct,     // no coupling: the (predicted) step force, low-passed and mapped
    Coupled,    // the coupling's spring renders the local model: the proxy steps
    RampingIn,  // coupled while safety ramps the force in: the steady part alone, the proxy placed
    Guided,     // the guide is engaged (weight > 0): the steady part on the played probe, blended
                // in by the guide's weight (with the coupling, the proxy placed)
  };
  // One period's decisions and what its stages hand on, made and read only inside tick().
  struct Period {
    TickMode mode = TickMode::Direct;
    bool enabled = false;          // output enabled and a simulation force in hand (safety's enabled)
    // Not homed, or not enabled with the force back at zero: the proxy starts again at the hand,
    // the passivity controller rests, the guide does not push.
    bool output_off = false;
    double sim_rate_hz = 0.0;      // the simulation's measured rate (0: no force yet), Hz
    glm::vec3 grip_m_s{0.0f};      // the grip's velocity fitted within the resolution (grip_), m/s
    glm::vec3 grip_now_m_s{0.0f};  // ... over the shortest span (grip_now_), m/s
    GuideTick guide;               // the playback guide's period
    glm::vec3 smoothed_n{0.0f};    // the low-passed fluid force, fluid N
    bool spring_rendered = false;  // the coupling's spring rendered this period's force
  };
  // The stages, in tick()'s order; each fills its part of TickOutput.
  Period followHand(const TickInput& in, TickOutput& out);
  void decide(const TickInput& in, Period& p) const;
  void fluidForce(const TickInput& in, TickOutput& out);
  void smooth(const TickInput& in, Period& p, TickOutput& out);
  void render(const TickInput& in, Period& p, TickOutput& out);
  void blendPlayed(const Period& p, TickOutput& out) const;
  void keepPassive(const TickInput& in, const Period& p, TickOutput& out);
  void addGuide(const Period& p, TickOutput& out) const;
  void clamp(const TickInput& in, const Period& p, TickOutput& out);
  void slipProxy(const TickInput& in, const Period& p, const TickOutput& out);

  PipelineSettings s_;
  bool coupled_ = false;           // s_.coupling.active(): the coupling renders (for the pipeline's life)
  LowPassSettings filter_in_use_;  // s_.filter, with the coupling's share of the bandwidth (filterFor)
  DragPredictor predictor_;
  FluidModel model_;
  VirtualCoupling coupling_;
  LowPassFilter filter_;
  // The grip's velocity (grip_motion.h): fitted within the device's resolution for the coupling's
  // damper (quiet at a slow push, where a damper on a count's jitter makes energy) and the
  // simulation's probe (TickOutput::grip_velocity_m_s), over the
  // shortest span for the passivity controller and the playback guide (2 ms of lag at the hand's
  // turns, where a damper must not push: with the fitted velocity the controller let gain 1 on a
  // 1500 N/m hand swing 37 mm, a 0.25 J window, test_haptic_passivity.py).
  GripMotion grip_;
  GripMotion grip_now_;
  PassivityController passivity_;
  ForceSafety safety_;
  PlaybackGuide guide_;
  glm::vec3 guide_held_{0.0f};  // the guide's part of the force the device held since the last tick
};

}  // namespace hf::haptics
