// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/force_pipeline.h"

#include <algorithm>
#include <cmath>

namespace hf::haptics {

namespace {
// What the coupling changes in the stages' settings, decided once for the pipeline's life:
// - The steady part's low-pass gets kSteadyBandwidthShare of the filter's bandwidth. The steady part
//   is meant to change slowly (buoyancy, the flow's push): the share keeps the step-to-step noise of
//   the identified residual (the simulation's reaction to the probe's own motion that the model did
//   not take out, held for a step) away from the hand.
// - The passivity controller does not act below kCoupledDeadbandM_s, whatever its own dead-band.
// - The local model's drag is kept at most the passivity controller's damping bound (the device's
//   maximum stable damping) once rendered: gain x |scale| x |B|. None: no bound.
LowPassSettings filterFor(const PipelineSettings& s) {
  LowPassSettings f = s.filter;
  if (s.coupling.active()) f.bandwidth_ratio *= kSteadyBandwidthShare;
  return f;
}

PassivitySettings passivityFor(const PipelineSettings& s) {
  PassivitySettings p = s.passivity;
  if (s.coupling.active()) p.velocity_deadband_m_s = std::max(p.velocity_deadband_m_s, kCoupledDeadbandM_s);
  return p;
}

double maxModelDrag(const PipelineSettings& s) {
  const glm::vec3 scale = glm::abs(s.map.scale);
  const double per_drag = static_cast<double>(s.map.force_gain) * std::max({scale.x, scale.y, scale.z});
  const double bound = s.passivity.max_damping_n_s_m.value_or(0.0f);
  return (bound > 0.0 && per_drag > 0.0) ? bound / per_drag : 1e30;
}
}  // namespace

glm::vec3 rampHeldForce(const glm::vec3& steady_n, const glm::vec3& grip_m_s) {
  const float speed = glm::length(grip_m_s);
  if (!(speed > kCoupledDeadbandM_s)) return steady_n;  // slow, or not finite: as it is
  const glm::vec3 along = grip_m_s / speed;
  const float push = glm::dot(steady_n, along);
  return push > 0.0f ? steady_n - push * along : steady_n;
}

void PipelineSettings::validate() const {
  map.validate();
  filter.validate();
  passivity.validate();
  safety.validate();
  coupling.validate();
  guide.validate();
}

ForcePipeline::ForcePipeline(const PipelineSettings& s)
    : s_((s.validate(), s)),
      coupled_(s.coupling.active()),
      filter_in_use_(filterFor(s)),
      model_(s.coupling.added_mass_kg, maxModelDrag(s)),
      coupling_(s.coupling.stiffness_n_m, s.coupling.damping_n_s_m),
      grip_(s.position_resolution_m),
      passivity_(passivityFor(s), s.safety.slew_rate_n_s),
      safety_(s.safety),
      guide_(s.guide) {}

TickOutput ForcePipeline::tick(const TickInput& in) {
  TickOutput out;
  out.coupled = coupled_;
  Period p = followHand(in, out);
  decide(in, p);
  fluidForce(in, out);
  smooth(in, p, out);
  render(in, p, out);
  blendPlayed(p, out);
  keepPassive(in, p, out);
  addGuide(p, out);
  clamp(in, p, out);
  slipProxy(in, p, out);
  return out;
}

// The grip's motion from the positions read (grip_motion.h), and the playback guide's period: the
// guide pulls the grip towards the played pose and, by its weight, hands the probe over to it.
ForcePipeline::Period ForcePipeline::followHand(const TickInput& in, TickOutput& out) {
  Period p;
  out.grip_m = in.state.position_m;
  p.grip_m_s = grip_.update(in.state.position_m, in.dt_s);
  p.grip_now_m_s = grip_now_.update(in.state.position_m, in.dt_s);
  out.grip_velocity_m_s =
      s_.position_resolution_m > 0.0 && allFinite(p.grip_m_s) ? p.grip_m_s : in.state.velocity_m_s;
  p.guide = guide_.step(in.guide, in.state.position_m, p.grip_now_m_s, in.now_s, in.dt_s);
  out.guide_weight = p.guide.weight;
  out.guide_target_m = p.guide.target_m;
  out.guide_target_m_s = p.guide.target_m_s;
  return p;
}

// This period's mode and whether its output is off, from the safety stage's state before this
// period's apply() (the force it last held, its ramp-in).
void ForcePipeline::decide(const TickInput& in, Period& p) const {
  p.enabled = in.enabled && in.have_force;
  p.output_off = !in.state.homed || (!p.enabled && safety_.last() == glm::vec3(0.0f));
  p.sim_rate_hz = in.have_force ? in.force.sim_rate_hz : 0.0;
  if (p.guide.weight > 0.0f) {
    p.mode = TickMode::Guided;
  } else if (!coupled_) {
    p.mode = TickMode::Direct;
  } else {
    p.mode = safety_.rampingIn() ? TickMode::RampingIn : TickMode::Coupled;
  }
}

// The simulation's force, and what the rendering makes of it between steps: the local model's
// steady part (coupled), the prediction F0 + B (v - v0) (prediction on) or the step force as it is.
void ForcePipeline::fluidForce(const TickInput& in, TickOutput& out) {
  if (!in.have_force) return;
  const ForceFrame& f = in.force;
  out.sim_force_n = out.predicted_n = f.force_n;
  out.force_age_s = in.now_s - f.publish_time_s;
  const bool usable = in.new_frame && allFinite(f.force_n) && allFinite(f.probe_velocity_m_s);
  if (coupled_) {
    if (usable) model_.addFrame(f.force_n, f.probe_velocity_m_s, f.step_dt_s);
    if (model_.frames() > 0 && allFinite(f.force_n)) out.predicted_n = model_.steadyN();
  } else if (s_.prediction) {
    if (usable) predictor_.addFrame(f.force_n, f.probe_velocity_m_s);
    if (predictor_.frames() > 0) out.predicted_n = predictor_.predict(s_.map.velocityToDomain(in.state.velocity_m_s));
  }
}

// The low-pass, its cutoff from the simulation's measured rate (filter_in_use_); it never lets a
// NaN into its memory and is emptied while no force is commanded, so force resumes from zero.
void ForcePipeline::smooth(const TickInput& in, Period& p, TickOutput& out) {
  p.smoothed_n = out.predicted_n;
  if (filter_in_use_.enabled) {
    out.cutoff_hz = cutoffForRate(filter_in_use_, p.sim_rate_hz);
    if (allFinite(out.predicted_n)) {
      p.smoothed_n = filter_.update(out.predicted_n, in.dt_s, out.cutoff_hz);
    } else {
      filter_.reset();
    }
  }
  if (!in.state.homed || !p.enabled) filter_.reset();
}

// The force the rendering asks for (device N): the low-passed force mapped, or with the coupling
// the proxy's. The proxy carries the model's mass and drag as the hand feels them: a device
// velocity v moves the probe at scale v and the hand gets gain x the fluid force, so per axis the
// rendered mass is gain |scale| m_a and the drag gain |scale| |B|; the steady part is mapped like a
// force. While the safety stage ramps the force in, the hand gets the steady part alone (the proxy
// placed, VirtualCoupling::place): a held force with no impedance behind it, whose work on a hand
// that yields to it (buoyancy in water lifting a 300 N/m hand 5 mm: 4 mJ) is the fluid's, not the
// rendering's; likewise while guided (blendPlayed), the proxy held placed at the hand.
void ForcePipeline::render(const TickInput& in, Period& p, TickOutput& out) {
  if (!coupled_) {
    out.filtered_n = s_.map.forceToDevice(p.smoothed_n);
    return;
  }
  out.drag_n_s_m = model_.dragNsM();
  const glm::vec3& hand_m = in.state.position_m;
  const bool hand_known = allFinite(hand_m) && allFinite(p.grip_m_s);
  if (p.output_off || !hand_known) coupling_.reset();
  if (!hand_known || !allFinite(p.smoothed_n)) {
    out.filtered_n = glm::vec3(NAN);  // safety zeroes it (and counts it)
    return;
  }
  const glm::vec3 steady = s_.map.forceToDevice(p.smoothed_n);
  if (p.mode == TickMode::Coupled) {
    const glm::vec3 per = s_.map.force_gain * glm::abs(s_.map.scale);
    const glm::vec3 mass = per * static_cast<float>(model_.addedMassKg());
    out.filtered_n = coupling_.step(hand_m, p.grip_m_s, mass, -per * model_.dragNsM(), steady, in.dt_s);
    p.spring_rendered = true;
  } else {
    coupling_.place(hand_m, p.grip_m_s, steady);
    out.filtered_n = p.mode == TickMode::RampingIn ? rampHeldForce(steady, p.grip_m_s) : steady;
  }
  out.proxy_m = glm::vec3(coupling_.proxyM());
}

// Haptic playback: while the guide is engaged the fluid's probe follows the played pose, not the
// hand, so the fluid is not an impedance the hand moves (a proxy whose mass and drag the hand drags
// would fight the guide). The hand gets the rendering's steady part on the played probe (the flow's
// push, buoyancy: low-passed, mapped), bounded to kPlayedForceShare of the guide's force so the
// guide keeps leading, blended in by the guide's weight.
void ForcePipeline::blendPlayed(const Period& p, TickOutput& out) const {
  if (p.mode != TickMode::Guided || !allFinite(out.filtered_n)) return;
  const glm::vec3 played = clampMagnitude(out.filtered_n, kPlayedForceShare * s_.guide.max_force_n);
  out.filtered_n += p.guide.weight * (played - out.filtered_n);
}

// The passivity controller. The observer sees the force the device held since the last reading
// (safety's last output, less the guide's part) and the grip's motion from the positions read
// (grip_motion.h), not the device's filtered velocity, which lags. A (re)start begins with no
// stored energy and no debt: it is reset while the output is off. It rests (reset) while guided:
// the hand moves because the guide moves it and the played force does not answer the hand's motion,
// so there is no rendering to keep passive; it starts afresh when the guide has let go. Likewise
// while the coupled rendering ramps in: counted, that work was a debt the controller paid with its
// full damping at the hand's first motion after the ramp (water, 48^3, a push at 25 mm/s: 0.3-0.6 N
// against gain x the fluid's drag, 0.02 N).
void ForcePipeline::keepPassive(const TickInput& in, const Period& p, TickOutput& out) {
  if (p.output_off || p.mode == TickMode::Guided || p.mode == TickMode::RampingIn) {
    passivity_.reset();
    out.passive_n = out.filtered_n;
  } else {
    // It works on the force the device can deliver (clamped to max_force): the energy it balances
    // is the energy the device can put in. Not acting, it passes the force on untouched. Coupled,
    // its dead-band (kCoupledDeadbandM_s) is held against the fitted speed: the shortest span's
    // jitter (a count in 4 ms, 10 mm/s) opened it in a slow push, and the damper on that jitter
    // made the energy it then took out of the push (water, 48^3, 12 mm/s: 0.2 N of damping where
    // gain x the fluid's drag is 0.015 N). It damps on the shortest span's velocity.
    const glm::vec3 deliverable = clampMagnitude(out.filtered_n, s_.safety.max_force_n);
    const double gate_m_s = p.mode == TickMode::Coupled && allFinite(p.grip_m_s)
                                ? static_cast<double>(glm::length(p.grip_m_s)) : -1.0;
    const glm::vec3 damped = passivity_.apply(deliverable, in.state.position_m, p.grip_now_m_s,
                                              safety_.last() - guide_held_, in.dt_s, gate_m_s);
    out.passive_n = passivity_.acted() ? damped : out.filtered_n;
  }
  out.damping_n_s_m = passivity_.state().alpha_n_s_m;
}

// The guide: after the controller (it moves the hand on purpose), before safety's clamp and slew.
// The played pose leads the probe whether or not force can be commanded (weight), but the guide
// pushes only a homed device whose output is on.
void ForcePipeline::addGuide(const Period& p, TickOutput& out) const {
  if (p.output_off || !allFinite(p.guide.force_n) || !allFinite(out.passive_n)) return;
  out.guide_n = p.guide.force_n;
  out.passive_n += p.guide.force_n;
}

// Safety, the last word on |F| (force_safety.h). Then what of the held force is the guide's (safety
// may have scaled the sum down): the observer's next period leaves it out.
void ForcePipeline::clamp(const TickInput& in, const Period& p, TickOutput& out) {
  SafetyInput safe;
  safe.force_n = out.passive_n;
  safe.dt_s = in.dt_s;
  safe.force_age_s = out.force_age_s;  // 0 without a force
  safe.sim_rate_hz = p.sim_rate_hz;
  safe.homed = in.state.homed;
  safe.enabled = p.enabled;
  out.commanded_n = safety_.apply(safe);
  out.commanded_domain_n = s_.map.forceToDomainAxes(out.commanded_n);
  out.stale_after_s = safety_.staleAfter();
  const float total = glm::length(out.passive_n), held = glm::length(out.commanded_n);
  guide_held_ = total > 0.0f && held < total ? out.guide_n * (held / total) : out.guide_n;
  if (!allFinite(guide_held_)) guide_held_ = glm::vec3(0.0f);
}

// The proxy feels what the hand got: where the controller or safety cut the spring's force, the
// spring slips (VirtualCoupling::yieldTo). Only after a spring step, when the guide (which holds the
// proxy placed while engaged) has no part in the command.
void ForcePipeline::slipProxy(const TickInput& in, const Period& p, const TickOutput& out) {
  if (p.spring_rendered && allFinite(out.commanded_n) && out.commanded_n != out.filtered_n) {
    coupling_.yieldTo(in.state.position_m, p.grip_m_s, out.commanded_n);
  }
}

void ForcePipeline::reset() {
  predictor_.reset();
  model_.reset();
  coupling_.reset();
  filter_.reset();
  grip_.reset();
  grip_now_.reset();
  passivity_.reset();
  safety_.reset();
  guide_.reset();
  guide_held_ = glm::vec3(0.0f);
}

}  // namespace hf::haptics
