// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/loop/haptic_loop.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/log_sink.h"
#include "haptics/devices/device_claim.h"
#include "haptics/handoff/clock.h"
#include "haptics/loop/periodic_clock.h"

namespace hf::haptics {

namespace {

DevicePtr requireDevice(DevicePtr device) {
  if (!device) throw InvalidArgument("haptic loop: give a device (got None)");
  return device;
}

HapticLoopSettings checkedAgainst(HapticLoopSettings s, const Device& device) {
  const float device_max = device.info().max_force_n;
  if (!(device_max > 0.0f)) {
    throw InvalidArgument("device '" + device.info().name + "' reports no maximum force (max_force_n = " +
                          std::to_string(device_max) + "); the haptic loop cannot bound its output");
  }
  if (s.pipeline.safety.max_force_n > device_max) {
    throw InvalidArgument("max_force " + std::to_string(s.pipeline.safety.max_force_n) + " N is above the maximum of '" +
                          device.info().name + "' (" + std::to_string(device_max) + " N); give at most that");
  }
  s.pipeline.position_resolution_m = device.info().position_resolution_m;
  // The passivity controller's damper is bounded by the device's maximum stable damping.
  // None takes the device's; a device that reports none leaves it None (observed only).
  std::optional<float>& damping = s.pipeline.passivity.max_damping_n_s_m;
  const float device_damping = device.info().max_damping_n_s_m;
  if (!damping) {
    if (device_damping > 0.0f) damping = device_damping;
  } else if (device_damping > 0.0f && *damping > device_damping) {
    throw InvalidArgument("passivity_max_damping " + std::to_string(*damping) + " N s/m is above the maximum stable damping of '" +
                          device.info().name + "' (" + std::to_string(device_damping) + " N s/m); give at most that");
  }
  // The virtual coupling's spring and damper: shares of the device's stable limits unless given
  // (a device that reports none keeps the seed's rendering: coupling.active() is false).
  CouplingSettings& c = s.pipeline.coupling;
  c = couplingOn(c, device.info());
  const float device_stiffness = device.info().max_stiffness_n_m;
  if (device_stiffness > 0.0f && c.stiffness_n_m > device_stiffness) {
    throw InvalidArgument("coupling_stiffness " + std::to_string(c.stiffness_n_m) + " N/m is above the maximum stiffness of '" +
                          device.info().name + "' (" + std::to_string(device_stiffness) + " N/m); give at most that");
  }
  if (device_damping > 0.0f && c.damping_n_s_m > device_damping) {
    throw InvalidArgument("coupling_damping " + std::to_string(c.damping_n_s_m) + " N s/m is above the maximum stable damping of '" +
                          device.info().name + "' (" + std::to_string(device_damping) + " N s/m); give at most that");
  }
  // The playback guide's spring and damper: shares of the device's limits unless given; the hand
  // touches the guide and the coupling together (in parallel), so their sums stay inside the limits.
  GuideSettings& g = s.pipeline.guide;
  if (g.stiffness_n_m == 0.0f) g.stiffness_n_m = kGuideStiffnessShare * device_stiffness;
  if (g.damping_n_s_m == 0.0f) g.damping_n_s_m = kGuideDampingShare * device_damping;
  if (g.max_force_n == 0.0f) g.max_force_n = kGuideForceShare * s.pipeline.safety.max_force_n;
  const float coupled_k = c.active() ? c.stiffness_n_m : 0.0f, coupled_b = c.active() ? c.damping_n_s_m : 0.0f;
  if (device_stiffness > 0.0f && g.stiffness_n_m + coupled_k > device_stiffness) {
    throw InvalidArgument("guide_stiffness " + std::to_string(g.stiffness_n_m) + " N/m with the coupling's " +
                          std::to_string(coupled_k) + " N/m is above the maximum stiffness of '" + device.info().name +
                          "' (" + std::to_string(device_stiffness) + " N/m); give at most " +
                          std::to_string(device_stiffness - coupled_k));
  }
  if (device_damping > 0.0f && g.damping_n_s_m + coupled_b > device_damping) {
    throw InvalidArgument("guide_damping " + std::to_string(g.damping_n_s_m) + " N s/m with the coupling's " +
                          std::to_string(coupled_b) + " N s/m is above the maximum stable damping of '" +
                          device.info().name + "' (" + std::to_string(device_damping) + " N s/m); give at most " +
                          std::to_string(device_damping - coupled_b));
  }
  if (g.max_force_n > s.pipeline.safety.max_force_n) {
    throw InvalidArgument("guide_max_force " + std::to_string(g.max_force_n) + " N is above max_force (" +
                          std::to_string(s.pipeline.safety.max_force_n) + " N); give at most that");
  }
  return s;
}

}  // namespace

CouplingSettings couplingOn(CouplingSettings c, const DeviceInfo& device) {
  if (c.stiffness_n_m == 0.0f) c.stiffness_n_m = kCouplingStiffnessShare * device.max_stiffness_n_m;
  if (c.damping_n_s_m == 0.0f) c.damping_n_s_m = kCouplingDampingShare * device.max_damping_n_s_m;
  return c;
}

void HapticLoopSettings::validate() const {
  if (!std::isfinite(rate_hz) || rate_hz < 100.0 || rate_hz > 10000.0) {
    throw InvalidArgument("haptic rate must be between 100 and 10000 Hz, got " + std::to_string(rate_hz));
  }
  if (realtime_priority < 1 || realtime_priority > 99) {
    throw InvalidArgument("realtime_priority must be 1..99 (SCHED_FIFO), got " + std::to_string(realtime_priority));
  }
  if (trace_capacity > (std::size_t{1} << 24)) {
    throw InvalidArgument("trace capacity must be at most 16777216 records, got " + std::to_string(trace_capacity));
  }
  pipeline.validate();
}

HapticLoop::HapticLoop(DevicePtr device, Mailbox<PoseFrame>& poses, const Mailbox<ForceFrame>& forces,
                       const HapticLoopSettings& settings)
    : device_(requireDevice(std::move(device))),
      poses_(poses),
      forces_(forces),
      s_((settings.validate(), checkedAgainst(settings, *device_))),
      pipeline_(s_.pipeline),
      trace_(s_.trace_capacity),
      reach_lo_m_(device_->info().workspace_min_m),
      reach_hi_m_(device_->info().workspace_max_m) {}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::start() {
  std::lock_guard<std::mutex> lock(thread_mutex_);
  if (thread_.joinable()) {
    throw Error("haptic loop: already started; a loop runs once (make a new one)");
  }
  auto claim = std::make_shared<DeviceClaim>(*device_, "start a haptic loop on it");
  stop_ = false;
  running_ = true;
  try {
    thread_ = std::thread([this, claim] { run(); });  // the claim ends with the thread
  } catch (...) {
    running_ = false;
    throw;
  }
}

void HapticLoop::stop() {
  // Under the lock: a start() racing with this stop() cannot clear the flag after it was set
  // and leave the join below waiting for a loop that was told to run on.
  std::lock_guard<std::mutex> lock(thread_mutex_);
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
}

void HapticLoop::setEnabled(bool on) { enabled_.store(on, std::memory_order_release); }

void HapticLoop::setGuide(const glm::vec3& position_m, const glm::vec3& velocity_m_s) {
  GuideTarget t;
  t.active = true;
  t.position_m = position_m;
  t.velocity_m_s = velocity_m_s;
  t.time_s = monotonicNowS();
  guide_.write(t);
}

void HapticLoop::releaseGuide() { guide_.write(GuideTarget{}); }

std::string HapticLoop::error() const { return failed() ? error_ : std::string(); }

std::exception_ptr HapticLoop::cause() const { return failed() ? cause_ : nullptr; }

void HapticLoop::run() {
  if (s_.realtime) {
    scheduling_ = requestRealtimePriority(s_.realtime_priority);
    realtime_ = scheduling_.empty();
    if (!scheduling_.empty()) log::warning("hapticfluid.haptics", scheduling_);  // queued: never the GIL here
  } else {
    scheduling_ = "real-time priority not requested (realtime=False); the period may jitter under load";
  }
  sched_known_.store(true, std::memory_order_release);

  PeriodicClock clock(1.0 / s_.rate_hz);
  const double nominal_s = clock.periodS();
  try {
    clock.start();
    double previous_s = monotonicNowS();
    // Once stop() is asked, periods run on with force disabled until the command has slewed
    // down to zero (max_force / slew_rate <= kMaxWindDownS, by SafetySettings::validate), so it
    // never drops at once; traced like any period. Counted in periods, not wall time, so a
    // loaded machine slows the wind-down but never cuts it: the guard (twice the periods the
    // longest wind-down needs) ends it only if the periods' dt ran short of nominal throughout.
    const auto max_wind_down_ticks = static_cast<std::uint64_t>(std::ceil(2.0 * kMaxWindDownS * s_.rate_hz));
    std::uint64_t wound_down = 0;
    for (;;) {
      const bool stopping = stop_.load(std::memory_order_acquire);
      if (stopping && (pipeline_.safety().last() == glm::vec3(0.0f) || wound_down++ >= max_wind_down_ticks)) break;
      const double now_s = clock.waitNext();
      const double dt_s = now_s - previous_s;
      previous_s = now_s;
      if (ticks_.load(std::memory_order_relaxed) > 0) periods_ms_.add(static_cast<float>(1e3 * dt_s));
      skipped_.store(clock.skipped(), std::memory_order_relaxed);
      // The filter and the slew limit see at most two nominal periods, so one late wake-up
      // cannot open a large force step.
      tickOnce(now_s, std::min(dt_s, 2.0 * nominal_s), !stopping);
      ticks_.fetch_add(1, std::memory_order_relaxed);
    }
    device_->zeroForce();
  } catch (const std::exception& e) {
    error_ = std::string("haptic loop stopped: ") + e.what();
    cause_ = std::current_exception();
    failed_.store(true, std::memory_order_release);
    device_->zeroForce();  // never throws: the device may be gone
  }
  latest_.write(TickOutput{});  // the host sees zero force once the loop has ended
  running_.store(false, std::memory_order_release);
}

void HapticLoop::tickOnce(double now_s, double dt_s, bool may_enable) {
  const DeviceState state = device_->read();
  latest_state_.write(state);
  const TickOutput out = pipeline_.tick(takeInputs(now_s, dt_s, may_enable, state));
  poses_.write(probePose(state, out, now_s));
  device_->writeForce(out.commanded_n);
  publish(state, out, now_s);
}

TickInput HapticLoop::takeInputs(double now_s, double dt_s, bool may_enable, const DeviceState& state) {
  TickInput in;
  // The played pose, if the host set one: into the device frame, inside the device's reach.
  GuideTarget host;
  if (guide_.tryRead(host)) played_ = host;  // a torn read keeps the last one
  if (played_.active) {
    last_played_ = played_;
    in.guide = played_;
    in.guide.position_m = glm::clamp(s_.pipeline.map.positionToDevice(played_.position_m), reach_lo_m_, reach_hi_m_);
    in.guide.velocity_m_s = s_.pipeline.map.velocityToDevice(played_.velocity_m_s);
  }
  std::uint64_t version = 0;
  ForceFrame frame;
  if (forces_.tryRead(frame, &version)) {
    force_ = frame;
    have_force_ = true;
    in.new_frame = version != force_version_;
    if (in.new_frame) {
      force_version_ = version;
      frames_.fetch_add(1, std::memory_order_relaxed);
      if (force_.pose_time_s > 0.0) latencies_ms_.add(static_cast<float>(1e3 * (now_s - force_.pose_time_s)));
    }
  }
  in.now_s = now_s;
  in.dt_s = dt_s;
  in.state = state;
  in.have_force = have_force_;
  in.force = force_;
  in.enabled = may_enable && enabled_.load(std::memory_order_acquire);
  return in;
}

PoseFrame HapticLoop::probePose(const DeviceState& state, const TickOutput& out, double now_s) const {
  const WorkspaceMap& map = s_.pipeline.map;
  // The grip's pose, with the velocity the pipeline chose for the simulation (TickOutput::grip_velocity_m_s).
  PoseFrame pose;
  pose.position_m = map.positionToDomain(state.position_m);
  pose.velocity_m_s = map.velocityToDomain(out.grip_velocity_m_s);
  if (out.guide_weight > 0.0f) {
    // With the guide engaged (weight w) the played pose, blended by w so the probe is handed over
    // between them without a step: the played pose itself as the host gave it, carried forward as
    // the guide carries it (not the device target, which is kept inside the device's reach); after
    // a release, the last one.
    const float w = out.guide_weight;
    const glm::vec3 played_m = carriedForward(last_played_, now_s, s_.pipeline.guide.stale_s);
    const glm::vec3 played_m_s = map.velocityToDomain(out.guide_target_m_s);
    pose.position_m += w * (played_m - pose.position_m);
    pose.velocity_m_s += w * (played_m_s - pose.velocity_m_s);
  }
  pose.time_s = now_s;
  pose.homed = state.homed;
  pose.has_orientation = state.has_orientation;
  if (state.has_orientation) {
    pose.orientation = map.orientationToDomain(state.orientation);
    pose.angular_velocity_rad_s = map.angularVelocityToDomain(state.angular_velocity_rad_s);
  }
  return pose;
}

void HapticLoop::publish(const DeviceState& state, const TickOutput& out, double now_s) {
  non_finite_.store(pipeline_.safety().nonFiniteCount(), std::memory_order_relaxed);
  passivity_.write(pipeline_.passivity().state());
  latest_.write(out);
  if (trace_.capacity() == 0) return;
  TraceSample t;
  t.time_s = now_s;
  t.position_m = state.position_m;
  t.sim_force_n = out.sim_force_n;
  t.filtered_n = out.filtered_n;
  t.commanded_n = out.commanded_n;
  t.guide_n = out.guide_n;
  if (have_force_) {
    t.step_velocity_m_s = force_.probe_velocity_m_s;
    t.step_dt_s = force_.step_dt_s;
    t.step_pose_time_s = force_.pose_time_s;
  }
  if (out.coupled) t.model_added_mass_kg = static_cast<float>(pipeline_.model().addedMassKg());
  trace_.push(t);
}

LoopStats HapticLoop::stats() const {
  LoopStats st;
  st.running = running();
  st.ticks = ticks_.load(std::memory_order_relaxed);
  const std::vector<float> periods = periods_ms_.values();
  st.period_ms = summarize(periods);
  std::vector<float> jitter(periods.size());
  const float nominal_ms = static_cast<float>(1e3 / s_.rate_hz);
  std::transform(periods.begin(), periods.end(), jitter.begin(), [&](float p) { return std::fabs(p - nominal_ms); });
  st.jitter_ms = summarize(std::move(jitter));
  st.rate_hz = st.period_ms.mean > 0.0 ? 1e3 / st.period_ms.mean : 0.0;
  st.latency_ms = summarize(latencies_ms_.values());
  st.skipped = skipped_.load(std::memory_order_relaxed);
  st.frames = frames_.load(std::memory_order_relaxed);
  st.non_finite = non_finite_.load(std::memory_order_relaxed);
  st.trace_dropped = trace_.dropped();
  passivity_.tryRead(st.passivity);
  st.max_damping_n_s_m = s_.pipeline.passivity.max_damping_n_s_m.value_or(0.0f);
  if (sched_known_.load(std::memory_order_acquire)) {
    st.realtime = realtime_.load(std::memory_order_relaxed);
    st.scheduling = scheduling_;
  }
  st.error = error();
  return st;
}

TickOutput HapticLoop::latest() const {
  TickOutput out;
  latest_.tryRead(out);
  return out;
}

DeviceState HapticLoop::latestState() const {
  DeviceState s;
  latest_state_.tryRead(s);
  return s;
}

}  // namespace hf::haptics
