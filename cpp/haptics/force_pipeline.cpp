#include "haptics/force_pipeline.h"

namespace hf::haptics {

void PipelineSettings::validate() const {
  map.validate();
  filter.validate();
  passivity.validate();
  safety.validate();
}

ForcePipeline::ForcePipeline(const PipelineSettings& s) : s_(s), passivity_(s.passivity, s.safety.slew_rate_n_s), safety_(s.safety) { s_.validate(); }

TickOutput ForcePipeline::tick(const TickInput& in) {
  TickOutput out;
  if (in.have_force) {
    out.sim_force_n = in.force.force_n;
    out.force_age_s = in.now_s - in.force.publish_time_s;
    if (in.new_frame && s_.prediction && allFinite(in.force.force_n)) {
      predictor_.addFrame(in.force.force_n, in.force.probe_velocity_m_s);
    }
    out.predicted_n = out.sim_force_n;
    if (s_.prediction && predictor_.frames() > 0) {
      out.predicted_n = predictor_.predict(s_.map.velocityToDomain(in.state.velocity_m_s));
    }
  }
  glm::vec3 smoothed = out.predicted_n;
  if (s_.filter.enabled) {
    out.cutoff_hz = cutoffForRate(s_.filter, in.have_force ? in.force.sim_rate_hz : 0.0);
    if (allFinite(out.predicted_n)) {
      smoothed = filter_.update(out.predicted_n, in.dt_s, out.cutoff_hz);
    } else {
      filter_.reset();  // never let a NaN into the filter's memory
    }
  }
  out.filtered_n = s_.map.forceToDevice(smoothed);
  // The observer sees the force the device held since the last reading: safety's last output.
  // A (re)start begins with no stored energy and no debt: it is reset while the device is not
  // homed, and while the output is off (paused, stopping, failed) with its force back at zero.
  // The controller acts on the grip's motion from the positions read (grip_motion.h), not on
  // the device's filtered velocity, which lags.
  const glm::vec3 grip_velocity = grip_.update(in.state.position_m, in.dt_s);
  const bool output_off = !in.state.homed || (!(in.enabled && in.have_force) && safety_.last() == glm::vec3(0.0f));
  if (output_off) {
    passivity_.reset();
    out.passive_n = out.filtered_n;
  } else {
    // The controller works on the force the device can deliver (clamped to max_force): the
    // energy it balances is then the energy the device can put in. Not acting, it passes the
    // force on untouched.
    const glm::vec3 deliverable = clampMagnitude(out.filtered_n, s_.safety.max_force_n);
    const glm::vec3 damped =
        passivity_.apply(deliverable, in.state.position_m, grip_velocity, safety_.last(), in.dt_s);
    out.passive_n = passivity_.acted() ? damped : out.filtered_n;
  }
  out.damping_n_s_m = passivity_.state().alpha_n_s_m;

  SafetyInput safe;
  safe.force_n = out.passive_n;
  safe.dt_s = in.dt_s;
  safe.force_age_s = in.have_force ? out.force_age_s : 0.0;
  safe.sim_rate_hz = in.have_force ? in.force.sim_rate_hz : 0.0;
  safe.homed = in.state.homed;
  safe.enabled = in.enabled && in.have_force;
  out.commanded_n = safety_.apply(safe);
  out.stale_after_s = safety_.staleAfter();
  if (!safe.homed || !safe.enabled) filter_.reset();
  return out;
}

void ForcePipeline::reset() {
  predictor_.reset();
  filter_.reset();
  grip_.reset();
  passivity_.reset();
  safety_.reset();
}

}  // namespace hf::haptics
