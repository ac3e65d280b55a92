// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/force_pipeline.h"

#include <algorithm>
#include <cmath>

namespace hf::haptics {

namespace {
// The local model's drag is kept at most the passivity controller's damping bound (the device's
// maximum stable damping) once rendered: gain x |scale| x |B|. None: no bound.
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
      model_(s.coupling.added_mass_kg, maxModelDrag(s)),
      coupling_(s.coupling.stiffness_n_m, s.coupling.damping_n_s_m),
      grip_(s.position_resolution_m),
      passivity_(passivityFor(s), s.safety.slew_rate_n_s),
      safety_(s.safety),
      guide_(s.guide) {}

TickOutput ForcePipeline::tick(const TickInput& in) {
  TickOutput out;
  if (in.have_force) {
    out.sim_force_n = in.force.force_n;
    out.force_age_s = in.now_s - in.force.publish_time_s;
    const bool coupled = s_.coupling.active();
    if (in.new_frame && allFinite(in.force.force_n) && allFinite(in.force.probe_velocity_m_s)) {
      if (coupled) {
        model_.addFrame(in.force.force_n, in.force.probe_velocity_m_s, in.force.step_dt_s);
      } else if (s_.prediction) {
        predictor_.addFrame(in.force.force_n, in.force.probe_velocity_m_s);
      }
    }
    out.predicted_n = out.sim_force_n;
    if (coupled && model_.frames() > 0 && allFinite(out.sim_force_n)) {
      out.predicted_n = model_.steadyN();
    } else if (!coupled && s_.prediction && predictor_.frames() > 0) {
      out.predicted_n = predictor_.predict(s_.map.velocityToDomain(in.state.velocity_m_s));
    }
  }
  glm::vec3 smoothed = out.predicted_n;
  if (s_.filter.enabled) {
    LowPassSettings filter = s_.filter;
    // The coupling's steady part is meant to change slowly (buoyancy, the flow's push): it gets a
    // kSteadyBandwidthShare of the cutoff, which keeps the step-to-step noise of the identified
    // residual (the simulation's reaction to the probe's own motion that the model did not take
    // out, held for a step) away from the hand.
    if (s_.coupling.active()) filter.bandwidth_ratio *= kSteadyBandwidthShare;
    out.cutoff_hz = cutoffForRate(filter, in.have_force ? in.force.sim_rate_hz : 0.0);
    if (allFinite(out.predicted_n)) {
      smoothed = filter_.update(out.predicted_n, in.dt_s, out.cutoff_hz);
    } else {
      filter_.reset();  // never let a NaN into the filter's memory
    }
  }
  const glm::vec3 grip_velocity = grip_.update(in.state.position_m, in.dt_s);
  const glm::vec3 grip_velocity_now = grip_now_.update(in.state.position_m, in.dt_s);
  out.grip_velocity_m_s =
      s_.position_resolution_m > 0.0 && allFinite(grip_velocity) ? grip_velocity : in.state.velocity_m_s;
  const bool output_off = !in.state.homed || (!(in.enabled && in.have_force) && safety_.last() == glm::vec3(0.0f));
  // Haptic playback: while the guide is engaged (weight w > 0) the fluid's probe follows the played
  // pose, not the hand, so the fluid is not an impedance the hand moves (a proxy whose mass and drag
  // the hand drags would fight the guide): the coupling's proxy is held placed at the hand (nothing
  // stored for the hand-over back) and the hand gets the rendering's steady part on the played probe
  // (the flow's push, buoyancy: low-passed, mapped), bounded to kPlayedForceShare of the guide's
  // force so the guide keeps leading, blended in by w.
  const GuideTick guide = guide_.step(in.guide, in.state.position_m, grip_velocity_now, in.now_s, in.dt_s);
  const float w = guide.weight;
  out.guide_weight = w;
  out.guide_target_m = guide.target_m;
  out.guide_target_m_s = guide.target_m_s;
  out.coupled = s_.coupling.active();
  bool coupled_step = false;  // the coupling's spring rendered this period's force
  // With the coupling, while the safety stage ramps the force in the hand gets the steady part
  // alone (the proxy placed): a held force with no impedance behind it, whose work on a hand that
  // yields to it (buoyancy in water lifting a 300 N/m hand 5 mm: 4 mJ) is the fluid's, not the
  // rendering's. The passivity controller rests through it (below), as it does while guided.
  const bool ramping = out.coupled && rampFactor(safety_.rampS(), s_.safety.ramp_s) < 1.0;
  if (out.coupled) {
    // The proxy carries the model's mass and drag as the hand feels them: a device velocity v moves
    // the probe at scale v, and the hand gets gain x the fluid force, so per axis the rendered
    // mass is gain |scale| m_a and the drag gain |scale| |B|; the steady part is mapped like a force.
    const glm::vec3 per = s_.map.force_gain * glm::abs(s_.map.scale);
    const glm::vec3 mass = per * static_cast<float>(model_.addedMassKg());
    const glm::vec3 drag = -per * model_.dragNsM();
    out.drag_n_s_m = model_.dragNsM();
    if (output_off || !allFinite(in.state.position_m) || !allFinite(grip_velocity)) coupling_.reset();
    if (allFinite(in.state.position_m) && allFinite(grip_velocity) && allFinite(smoothed)) {
      const glm::vec3 steady = s_.map.forceToDevice(smoothed);
      if (ramping || w > 0.0f) {  // the steady force alone, the proxy placed (VirtualCoupling::place)
        coupling_.place(in.state.position_m, grip_velocity, steady);
        out.filtered_n = ramping && w == 0.0f ? rampHeldForce(steady, grip_velocity) : steady;
      } else {
        out.filtered_n = coupling_.step(in.state.position_m, grip_velocity, mass, drag, steady, in.dt_s);
        coupled_step = true;
      }
      out.proxy_m = glm::vec3(coupling_.proxyM());
    } else {
      out.filtered_n = glm::vec3(NAN);  // safety zeroes it (and counts it)
    }
  } else {
    out.filtered_n = s_.map.forceToDevice(smoothed);
  }
  if (w > 0.0f && allFinite(out.filtered_n)) {
    const glm::vec3 played = clampMagnitude(out.filtered_n, kPlayedForceShare * s_.guide.max_force_n);
    out.filtered_n += w * (played - out.filtered_n);
  }
  // The observer sees the force the device held since the last reading: safety's last output.
  // A (re)start begins with no stored energy and no debt: it is reset while the device is not
  // homed, and while the output is off (paused, stopping, failed) with its force back at zero.
  // The controller acts on the grip's motion from the positions read (grip_motion.h), not on
  // the device's filtered velocity, which lags.
  // While the guide is engaged the controller rests (reset): the hand moves because the guide moves
  // it and the played force does not answer the hand's motion, so there is no rendering for it to
  // keep passive; it starts afresh, with nothing stored, when the guide has let go. Likewise while
  // the coupled rendering ramps in (the steady part alone): counted, that work was a debt the
  // controller paid with its full damping at the hand's first motion after the ramp (water, 48^3,
  // a push at 25 mm/s: 0.3-0.6 N against gain x the fluid's drag, 0.02 N).
  if (output_off || w > 0.0f || ramping) {
    passivity_.reset();
    out.passive_n = out.filtered_n;
  } else {
    // The controller works on the force the device can deliver (clamped to max_force): the
    // energy it balances is then the energy the device can put in. Not acting, it passes the
    // force on untouched.
    const glm::vec3 deliverable = clampMagnitude(out.filtered_n, s_.safety.max_force_n);
    // With the coupling the dead-band (kCoupledDeadbandM_s) is held against the fitted speed: the
    // shortest span's jitter (a count in 4 ms, 10 mm/s) opened it in a slow push, and the
    // controller's damper on that jitter made the energy it then took out of the push (water, 48^3,
    // 12 mm/s: 0.2 N of damping where gain x the fluid's drag is 0.015 N). It damps on the
    // shortest span's velocity, which has 2 ms of lag at the hand's turns.
    const double gate_m_s = out.coupled && allFinite(grip_velocity) ? static_cast<double>(glm::length(grip_velocity)) : -1.0;
    const glm::vec3 damped = passivity_.apply(deliverable, in.state.position_m, grip_velocity_now,
                                              safety_.last() - guide_held_, in.dt_s, gate_m_s);
    out.passive_n = passivity_.acted() ? damped : out.filtered_n;
  }
  out.damping_n_s_m = passivity_.state().alpha_n_s_m;
  // The guide: after the controller (it moves the hand on purpose), before safety's clamp and slew.
  // The played pose leads the probe whether or not force can be commanded (weight), but the guide
  // pushes only a homed device whose output is on.
  if (!output_off && allFinite(guide.force_n) && allFinite(out.passive_n)) {
    out.guide_n = guide.force_n;
    out.passive_n += guide.force_n;
  }

  SafetyInput safe;
  safe.force_n = out.passive_n;
  safe.dt_s = in.dt_s;
  safe.force_age_s = in.have_force ? out.force_age_s : 0.0;
  safe.sim_rate_hz = in.have_force ? in.force.sim_rate_hz : 0.0;
  safe.homed = in.state.homed;
  safe.enabled = in.enabled && in.have_force;
  out.commanded_n = safety_.apply(safe);
  out.commanded_domain_n = s_.map.forceToDomainAxes(out.commanded_n);
  // What of the held force is the guide's (safety may have scaled the sum down): the observer's
  // next period leaves it out.
  {
    const float total = glm::length(out.passive_n), held = glm::length(out.commanded_n);
    guide_held_ = total > 0.0f && held < total ? out.guide_n * (held / total) : out.guide_n;
    if (!allFinite(guide_held_)) guide_held_ = glm::vec3(0.0f);
  }
  // The proxy feels what the hand got: where the controller or safety cut the force, the spring slips.
  // With the guide on, what the fluid's rendering delivered is the command less the guide's part.
  const bool guided = out.guide_n != glm::vec3(0.0f);
  const glm::vec3 fluid_delivered = guided ? out.commanded_n - guide_held_ : out.commanded_n;
  const bool cut = guided ? glm::length(fluid_delivered - out.filtered_n) > 1e-5f * (1.0f + glm::length(out.filtered_n))
                          : out.commanded_n != out.filtered_n;
  if (out.coupled && coupled_step && allFinite(fluid_delivered) && cut) {
    coupling_.yieldTo(in.state.position_m, grip_velocity, fluid_delivered);
  }
  out.stale_after_s = safety_.staleAfter();
  if (!safe.homed || !safe.enabled) filter_.reset();
  return out;
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
