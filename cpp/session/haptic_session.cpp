// SPDX-License-Identifier: GPL-3.0-or-later
#include "session/haptic_session.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/error.h"
#include "common/finite.h"
#include "common/format.h"
#include "fluid/validate.h"
#include "haptics/handoff/clock.h"
#include "haptics/loop/rate_estimator.h"
#include "haptics/rendering/rendering_limits.h"
#include "session/simulation.h"
#include "session/simulation_claim.h"

namespace hf::session {

namespace {
constexpr double kDtSmoothing = 0.25;  // real time: weight of the newest wall period in the step
constexpr float kDefaultProbeRadiusM = 0.1f;  // the sphere made when there is no probe to keep
constexpr double kPi = 3.14159265358979323846;

// The settings with the force gain in use: derived from the device's rendering limits and the
// probe's added mass (a sphere's volume, or a mesh probe's world box: an upper bound), or given.
HapticSessionSettings withForceGain(HapticSessionSettings s, const Simulation& sim, const haptics::DevicePtr& device) {
  if (!device) throw InvalidArgument("haptic session: give a device (got None)");
  float& gain = s.loop.pipeline.map.force_gain;
  const std::optional<ProbeState> probe = sim.probe();
  double volume_m3 = 0.0;
  if (s.probe_radius_m || !probe || probe->kind == ProbeState::Kind::Sphere) {
    const double r = s.probe_radius_m ? *s.probe_radius_m : probe ? probe->sphere.radius_m : kDefaultProbeRadiusM;
    volume_m3 = 4.0 / 3.0 * kPi * r * r * r;
  } else {
    const obstacle::WorldBox box = obstacle::worldBox(probe->extent, probe->pose.transform);
    const glm::dvec3 edge(box.hi - box.lo);
    volume_m3 = edge.x * edge.y * edge.z;
  }
  const double added_kg = haptics::addedMassKg(sim.params().density_kg_m3, volume_m3);
  s.loop.pipeline.coupling.added_mass_kg = added_kg;  // the local model's added mass
  const glm::vec3 scale = glm::abs(s.loop.pipeline.map.scale);
  const double step_s = s.sim_dt_s > 0.0 ? s.sim_dt_s : s.min_sim_dt_s;
  const haptics::DeviceInfo info = device->info();
  const bool coupled = haptics::couplingOn(s.loop.pipeline.coupling, info).active();
  const double max_scale = std::max({scale.x, scale.y, scale.z});
  // At rest the probe feels buoyancy: rho |g| V (N).
  const double steady_n = sim.params().density_kg_m3 * glm::length(glm::dvec3(sim.params().gravity_m_s2)) * volume_m3;
  const haptics::GainChoice c =
      coupled ? haptics::coupledForceGain(info, added_kg, max_scale, step_s, steady_n, s.loop.pipeline.safety.max_force_n)
              : haptics::renderableForceGain(info, added_kg, max_scale, step_s);
  if (!s.derive_force_gain) {
    // A given gain above what the rendering holds passively only with allow_unsafe_gain.
    if (gain > c.gain * (1.0f + 1e-4f) && !s.allow_unsafe_gain) {
      throw InvalidArgument("force_gain " + num3(gain) + " is more than this device renders passively here (" + c.reason +
                            "); give at most " + num3(c.gain) + ", None to derive it, or allow_unsafe_gain=True: the "
                            "rendering may then put energy into the hand (oscillation, a kick when the probe meets "
                            "the fluid's push)");
    }
    s.force_gain_reason = "force gain " + num(gain) + ": given" +
                          (gain > c.gain * (1.0f + 1e-4f) ? " (unsafe: above the passive " + num3(c.gain) + ")" : "");
    return s;
  }
  gain = c.gain;
  s.force_gain_reason = c.reason;
  if (s.feel == Feel::Physical) {  // 1:1, where the rendering holds it passively
    if (c.gain >= 1.0f) {
      gain = 1.0f;
      s.force_gain_reason = "force gain 1: physical (1:1), the fluid's newtons on the hand (the rendering holds up to " +
                            num3(c.gain) + ")";
    } else {
      s.force_gain_reason = "physical (1:1) is more than the rendering holds passively here: " + c.reason;
    }
  }
  return s;
}
}  // namespace

std::pair<glm::vec3, glm::vec3> HapticSession::workspaceBox() const {
  const haptics::DeviceInfo info = device_->info();
  const haptics::WorkspaceMap& map = s_.loop.pipeline.map;
  const glm::vec3 a = map.positionToDomain(info.workspace_min_m), b = map.positionToDomain(info.workspace_max_m);
  return {glm::min(a, b), glm::max(a, b)};
}

const char* feelName(Feel f) { return f == Feel::Physical ? "physical" : "amplified"; }

Feel feelFromName(const std::string& name) {
  if (name == "amplified") return Feel::Amplified;
  if (name == "physical") return Feel::Physical;
  throw InvalidArgument("feel must be 'amplified' (the largest gain the rendering holds passively) or 'physical' (1:1), got '" +
                        name + "'");
}

const char* stateName(SessionState s) {
  switch (s) {
    case SessionState::Idle: return "idle";
    case SessionState::Running: return "running";
    case SessionState::Paused: return "paused";
    case SessionState::Stopped: return "stopped";
    case SessionState::Failed: return "failed";
  }
  return "unknown";
}

void HapticSessionSettings::validate() const {
  loop.validate();
  if (probe_radius_m && (!std::isfinite(*probe_radius_m) || *probe_radius_m <= 0.0f)) {
    throw InvalidArgument("probe_radius must be a positive number of metres (or None: keep the simulation's probe), got " +
                          std::to_string(*probe_radius_m));
  }
  if (!std::isfinite(max_sim_dt_s) || max_sim_dt_s < fluid::kMinTimeStep || max_sim_dt_s > fluid::kMaxTimeStep) {
    throw InvalidArgument("max_sim_dt must be between 1e-6 and 10 s, got " + std::to_string(max_sim_dt_s));
  }
  if (!std::isfinite(min_sim_dt_s) || min_sim_dt_s < fluid::kMinTimeStep || min_sim_dt_s > max_sim_dt_s) {
    throw InvalidArgument("min_sim_dt must be between 1e-6 s and max_sim_dt (" + std::to_string(max_sim_dt_s) +
                          " s), got " + std::to_string(min_sim_dt_s));
  }
  if (!std::isfinite(sim_dt_s) || (sim_dt_s != 0.0 && (sim_dt_s < fluid::kMinTimeStep || sim_dt_s > fluid::kMaxTimeStep))) {
    throw InvalidArgument("sim_dt must be 0 (real time) or between 1e-6 and 10 s, got " + std::to_string(sim_dt_s));
  }
  if (workspace_offset_m && !allFinite(*workspace_offset_m)) {
    throw InvalidArgument("workspace_offset must be finite metres (or None: centred), got " + vecText(*workspace_offset_m));
  }
  if (!(max_cutoff_per_rate > 0.0 && max_cutoff_per_rate <= 0.5)) {
    throw InvalidArgument("the low-pass cutoff's bound must be a fraction of the haptic rate in (0, 0.5], got " +
                          std::to_string(max_cutoff_per_rate));
  }
  // The rate is checked here too (loop.validate() says so with its own words) so the trace's
  // size below never meets a NaN or negative rate.
  if (trace && (!(trace_s > 0.0) || !(loop.rate_hz > 0.0) || trace_s * loop.rate_hz > double(std::size_t{1} << 24))) {
    throw InvalidArgument("trace_seconds must be > 0 and at most 16777216 haptic periods, got " +
                          std::to_string(trace_s) + " s");
  }
  if (snapshot_interval_s && !(*snapshot_interval_s >= 0.0 && *snapshot_interval_s <= 3600.0)) {
    throw InvalidArgument("snapshot must be None (off), 0 (after every step) or seconds between snapshots up to "
                          "3600, got " + std::to_string(*snapshot_interval_s));
  }
}

HapticSessionSettings HapticSessionSettings::resolve(const glm::vec3& domain_origin_m, const glm::vec3& domain_size_m,
                                                     const haptics::DeviceInfo& device) const {
  validate();
  HapticSessionSettings r = *this;
  auto& p = r.loop.pipeline;
  if (fit_workspace) {
    const glm::vec3 ws = device.workspace_max_m - device.workspace_min_m;
    if (!(ws.x > 0.0f && ws.y > 0.0f && ws.z > 0.0f)) {
      throw InvalidArgument("fit_workspace: the device '" + device.name + "' reports no workspace " + vecText(ws) +
                            " m; give a workspace_scale instead");
    }
    const glm::vec3 fit = domain_size_m / ws;
    p.map.scale = glm::sign(p.map.scale) * std::min({fit.x, fit.y, fit.z});
  }
  p.map.offset_m = workspace_offset_m ? *workspace_offset_m
                                      : domain_origin_m + 0.5f * domain_size_m -
                                            p.map.scale * (0.5f * (device.workspace_min_m + device.workspace_max_m));
  p.filter.max_cutoff_hz = max_cutoff_per_rate * r.loop.rate_hz;
  r.loop.trace_capacity = trace ? static_cast<std::size_t>(trace_s * r.loop.rate_hz) + 1 : 0;
  p.safety.max_force_n = max_force_n ? *max_force_n : device.max_force_n;
  r.loop.validate();
  return r;
}

HapticSession::HapticSession(Simulation& sim, haptics::DevicePtr device, const HapticSessionSettings& settings)
    : sim_(sim),
      device_(std::move(device)),
      s_(withForceGain(settings.resolve(sim.grid().origin_m, sim.grid().sizeM(),
                                        device_ ? device_->info() : haptics::DeviceInfo{}),
                       sim, device_)),
      loop_(device_, poses_, forces_, s_.loop) {
  // Not while another session drives this simulation: the probe set below would replace its probe.
  { SimulationClaim free_now(sim_, "make a haptic session on it"); }
  const fluid::Grid& g = sim_.grid();
  const std::optional<ProbeState> current = sim_.probe();
  const float margin = g.cell_size_m * 1.001f;  // a hair more than the simulation's one cell
  // The probe's world box relative to its origin (translation-invariant: orientation is kept).
  glm::vec3 lo_offset(0.0f), hi_offset(0.0f);
  if (s_.probe_radius_m || !current) {
    // A new sphere in the middle of the domain: the simulation checks the radius against the
    // grid here, with its own message, before any thread starts.
    const float r = s_.probe_radius_m.value_or(kDefaultProbeRadiusM);
    obstacle::SpherePose sphere;
    sphere.centre_m = g.origin_m + 0.5f * g.sizeM();
    sphere.radius_m = r;
    sim_.setSphereProbe(sphere);
    lo_offset = glm::vec3(-r);
    hi_offset = glm::vec3(r);
  } else if (current->kind == ProbeState::Kind::Sphere) {
    lo_offset = glm::vec3(-current->sphere.radius_m);
    hi_offset = glm::vec3(current->sphere.radius_m);
  } else {
    base_transform_ = current->pose.transform;
    const obstacle::WorldBox box = obstacle::worldBox(current->extent, base_transform_);
    const glm::vec3 origin(base_transform_[3]);
    lo_offset = box.lo - origin;
    hi_offset = box.hi - origin;
    mesh_probe_ = true;
    extent_ = current->extent;
    local_scale_ = glm::transpose(probeRotation(base_transform_)) * glm::mat3(base_transform_);
  }
  wall_lo_m_ = g.origin_m + margin;
  wall_hi_m_ = g.origin_m + g.sizeM() - margin;
  probe_lo_m_ = wall_lo_m_ - lo_offset;
  probe_hi_m_ = wall_hi_m_ - hi_offset;
  if (glm::any(glm::greaterThan(probe_lo_m_, probe_hi_m_))) {
    throw InvalidArgument("the simulation's probe (" + vecText(hi_offset - lo_offset) +
                          " m across) cannot move inside the domain with one cell of fluid to every wall; "
                          "make it smaller or the domain larger");
  }
}

HapticSession::~HapticSession() {
  try {
    stop(3600.0);
  } catch (...) {  // errors were available through error(); a destructor must not throw
  }
  joinAll();
}

glm::mat3 HapticSession::probeRotation(const glm::mat4& transform) {
  const glm::vec3 x = glm::normalize(glm::vec3(transform[0]));
  const glm::vec3 y = glm::normalize(glm::vec3(transform[1]) - glm::dot(glm::vec3(transform[1]), x) * x);
  return glm::mat3(x, y, glm::cross(x, y));
}

glm::vec3 HapticSession::probeOriginFor(const glm::vec3& device_position_m) const {
  haptics::PoseFrame pose;
  pose.position_m = s_.loop.pipeline.map.positionToDomain(device_position_m);
  return glm::vec3(poseFor(pose).transform[3]);
}

obstacle::RigidPose HapticSession::poseFor(const haptics::PoseFrame& pose) const {
  obstacle::RigidPose p;
  p.transform = base_transform_;
  glm::vec3 lo = probe_lo_m_, hi = probe_hi_m_;
  glm::vec3 spin(0.0f);
  const glm::quat q = pose.orientation;
  const float q_norm = glm::length(q);
  if (pose.has_orientation && std::isfinite(q_norm) && q_norm > 1e-6f) {
    bool fits = true;
    glm::mat4 turned(glm::mat3_cast(q / q_norm) * local_scale_);
    if (mesh_probe_) {  // the turned probe's world box about its origin, O(1)
      const obstacle::WorldBox box = obstacle::worldBox(extent_, turned);
      const glm::vec3 turned_lo = wall_lo_m_ - box.lo, turned_hi = wall_hi_m_ - box.hi;
      fits = !glm::any(glm::greaterThan(turned_lo, turned_hi));
      if (fits) {
        lo = turned_lo;
        hi = turned_hi;
        p.transform = turned;
      }
    }
    if (fits && allFinite(pose.angular_velocity_rad_s)) spin = pose.angular_velocity_rad_s;
  }
  glm::vec3 origin = glm::clamp(pose.position_m, lo, hi);
  glm::vec3 velocity = pose.velocity_m_s;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(origin[a])) origin[a] = 0.5f * (lo[a] + hi[a]);
    // Held at a wall: the probe does not move along that axis.
    if (origin[a] != pose.position_m[a] || !std::isfinite(velocity[a])) velocity[a] = 0.0f;
  }
  // Scaled to a hair under the simulation's limit (in double: the length of a huge vector
  // overflows in float), so the rounding of the scaled vector never lands above it: a pose
  // stream the simulation would refuse must not end the session.
  const glm::dvec3 v(velocity);
  const double speed = glm::length(v);
  const double max_speed = static_cast<double>(fluid::kMaxProbeSpeed) * (1.0 - 1e-4);
  if (speed > max_speed) velocity = glm::vec3(v * (max_speed / speed));
  const glm::dvec3 w(spin);
  const double spin_rate = glm::length(w);
  const double max_spin = static_cast<double>(fluid::kMaxProbeSpin) * (1.0 - 1e-4);
  if (spin_rate > max_spin) spin = glm::vec3(w * (max_spin / spin_rate));
  p.transform[3] = glm::vec4(origin, 1.0f);
  p.velocity_m_s = velocity;
  p.angular_velocity_rad_s = spin;
  return p;
}

void HapticSession::setGuide(const glm::vec3& position_m, const glm::vec3& velocity_m_s) {
  if (!allFinite(position_m)) {
    throw InvalidArgument("set_guide: position must be finite world metres, got " + vecText(position_m));
  }
  if (!allFinite(velocity_m_s) || glm::length(glm::dvec3(velocity_m_s)) > fluid::kMaxProbeSpeed) {
    throw InvalidArgument("set_guide: velocity must be finite m/s with a speed of at most " +
                          std::to_string(fluid::kMaxProbeSpeed) + " m/s (the simulation's probe limit), got " +
                          vecText(velocity_m_s));
  }
  loop_.setGuide(position_m, velocity_m_s);
}

void HapticSession::start() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (state_.load() != SessionState::Idle || sim_thread_.joinable()) {
    throw Error("haptic session: start() runs once per session (state '" + std::string(stateName(state_.load())) +
                "'); make a new HapticSession");
  }
  auto claim = std::make_unique<SimulationClaim>(sim_, "start a haptic session on it");
  loop_.start();  // throws if the device is held: the simulation's claim ends here too
  sim_thread_ = std::thread([this] { simLoop(); });
  sim_claim_ = std::move(claim);
  state_.store(SessionState::Running, std::memory_order_release);
}

void HapticSession::pause() {
  std::lock_guard<std::mutex> lock(mutex_);
  const SessionState st = state_.load();
  if (st == SessionState::Idle) throw Error("haptic session: pause() before start()");
  if (st != SessionState::Running) return;  // already paused, stopped or failed: nothing to hold
  paused_ = true;
  loop_.setEnabled(false);
  state_.store(SessionState::Paused, std::memory_order_release);
}

void HapticSession::resume() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const SessionState st = state_.load();
    if (st == SessionState::Failed) throw Error("haptic session: cannot resume, it failed: " + error_);
    if (st != SessionState::Paused) return;
    paused_ = false;
    loop_.setEnabled(true);
    state_.store(SessionState::Running, std::memory_order_release);
  }
  cv_.notify_all();
}

void HapticSession::fail(const std::string& message, std::exception_ptr cause) {
  loop_.setEnabled(false);
  std::lock_guard<std::mutex> lock(mutex_);
  if (error_.empty()) {
    error_ = message;
    cause_ = cause;
  }
  state_.store(SessionState::Failed, std::memory_order_release);
}

std::string HapticSession::error() const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_.empty()) return error_;
  }
  return loop_.error();
}

void HapticSession::stop(double timeout_s) {
  if (!(timeout_s >= 0.0) || !std::isfinite(timeout_s)) {
    throw InvalidArgument("stop timeout must be a finite number of seconds >= 0, got " + std::to_string(timeout_s));
  }
  std::lock_guard<std::mutex> stopping(stop_mutex_);  // a second stop() waits, then finds the threads gone
  loop_.setEnabled(false);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = true;
  }
  cv_.notify_all();
  loop_.stop();  // slews down (at most kMaxWindDownS), joins; the device got its last zero
  if (loop_.failed()) fail(loop_.error(), loop_.cause());
  std::unique_lock<std::mutex> lock(mutex_);
  // Force output has ended: say so now, even if the simulation's last step is still running.
  if (state_.load() != SessionState::Failed) state_.store(SessionState::Stopped, std::memory_order_release);
  if (sim_thread_.joinable()) {
    const auto limit = std::chrono::duration<double>(timeout_s);
    if (!cv_.wait_for(lock, limit, [this] { return sim_done_; })) {
      throw Error("haptic session: the simulation's current step is still running after " + std::to_string(timeout_s) +
                  " s; force output has stopped; call stop() again to wait longer");
    }
    lock.unlock();
    sim_thread_.join();
    lock.lock();
  }
  sim_claim_.reset();  // the simulation thread is down: another session may drive it
  if (state_.load() != SessionState::Failed) state_.store(SessionState::Stopped, std::memory_order_release);
  if (!error_.empty() && !error_raised_) {
    error_raised_ = true;
    if (cause_) {  // the haptic loop's failure: the device's own error (its type kept), or a DeviceError
      try {
        std::rethrow_exception(cause_);
      } catch (const DeviceError&) {
        throw;
      } catch (...) {
        throw DeviceError(error_);
      }
    }
    throw Error(error_);
  }
}

void HapticSession::joinAll() {
  std::lock_guard<std::mutex> stopping(stop_mutex_);
  loop_.stop();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = true;
  }
  cv_.notify_all();
  if (sim_thread_.joinable()) sim_thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  sim_claim_.reset();
}

void HapticSession::simLoop() {
  haptics::RateEstimator rate;
  double last_start_s = -1.0;
  double smooth_dt_s = s_.min_sim_dt_s;
  try {
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (paused_) {
          cv_.wait(lock, [this] { return stop_requested_ || !paused_; });
          last_start_s = -1.0;  // real time restarts after a pause
          smooth_dt_s = s_.min_sim_dt_s;
          rate.reset();
        }
        if (stop_requested_ || state_.load() == SessionState::Failed) break;
      }
      if (loop_.failed()) {
        fail(loop_.error(), loop_.cause());
        break;
      }
      haptics::PoseFrame pose;
      if (!poses_.tryRead(pose)) {  // the haptic thread has not read the device yet
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      const obstacle::RigidPose probe = poseFor(pose);
      sim_.setProbePose(probe);
      const double start_s = haptics::monotonicNowS();
      double dt_s = s_.sim_dt_s;
      if (dt_s <= 0.0) {  // real time: the smoothed wall period, so one slow step does not jolt dt
        if (last_start_s >= 0.0) smooth_dt_s += kDtSmoothing * (start_s - last_start_s - smooth_dt_s);
        dt_s = std::clamp(smooth_dt_s, s_.min_sim_dt_s, s_.max_sim_dt_s);
      }
      last_start_s = start_s;
      const StepReport report = sim_.step(dt_s);
      const double done_s = haptics::monotonicNowS();
      rate.add(done_s);
      haptics::ForceFrame frame;
      frame.force_n = report.force_n;
      frame.probe_velocity_m_s = probe.velocity_m_s;
      frame.pose_time_s = pose.time_s;
      frame.publish_time_s = done_s;
      frame.sim_rate_hz = rate.rateHz();
      frame.step_dt_s = dt_s;
      forces_.write(frame);
      sim_steps_.fetch_add(1, std::memory_order_relaxed);
      sim_rate_hz_.store(rate.rateHz(), std::memory_order_relaxed);
      sim_step_ms_.store(1e3 * (done_s - start_s), std::memory_order_relaxed);
      sim_dt_s_.store(dt_s, std::memory_order_relaxed);
      publishSnapshot(done_s);
      if (s_.sim_dt_s <= 0.0) {  // real time: no faster than one step per min_sim_dt_s of wall time
        std::unique_lock<std::mutex> lock(mutex_);
        const auto until = std::chrono::duration<double>(start_s + s_.min_sim_dt_s - haptics::monotonicNowS());
        if (until.count() > 0.0) cv_.wait_for(lock, until, [this] { return stop_requested_ || paused_; });
      }
    }
  } catch (const std::exception& e) {
    fail(std::string("simulation thread stopped: ") + e.what());
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    sim_done_ = true;
  }
  cv_.notify_all();
}

void HapticSession::publishSnapshot(double now_s) {
  if (!s_.snapshot_interval_s) return;
  if (last_snapshot_s_ >= 0.0 && now_s - last_snapshot_s_ < *s_.snapshot_interval_s) return;
  auto snap = std::make_shared<FieldSnapshot>();
  snap->resolution = sim_.grid().res;
  snap->density = sim_.readFloat(Field::Density);  // this thread waits for the GPU, the host never does
  if (s_.snapshot_temperature) snap->temperature = sim_.readFloat(Field::Temperature);
  snap->time_s = sim_.timeS();  // only this thread steps, so the clock is the step's
  snap->steps = sim_.steps();
  snap->sequence = ++snapshot_sequence_;
  last_snapshot_s_ = now_s;
  std::shared_ptr<const FieldSnapshot> old;
  {
    std::lock_guard<std::mutex> lock(snapshot_mutex_);
    old = std::move(snapshot_);
    snapshot_ = std::move(snap);
  }
  snapshots_.store(snapshot_sequence_, std::memory_order_relaxed);
  // `old` is freed here, outside the lock (unless the host still holds it).
}

std::shared_ptr<const FieldSnapshot> HapticSession::fieldSnapshot() const {
  std::lock_guard<std::mutex> lock(snapshot_mutex_);
  return snapshot_;
}

SessionState HapticSession::state() const {
  return loop_.failed() ? SessionState::Failed : state_.load(std::memory_order_acquire);
}

HapticSessionStats HapticSession::stats() const {
  HapticSessionStats st;
  st.haptic = loop_.stats();
  st.state = state();
  st.sim_rate_hz = sim_rate_hz_.load(std::memory_order_relaxed);
  st.sim_steps = sim_steps_.load(std::memory_order_relaxed);
  st.sim_step_ms = sim_step_ms_.load(std::memory_order_relaxed);
  st.sim_dt_s = sim_dt_s_.load(std::memory_order_relaxed);
  st.snapshots = snapshots_.load(std::memory_order_relaxed);
  st.stale_after_s = loop_.latest().stale_after_s;
  st.force_gain = s_.loop.pipeline.map.force_gain;
  st.force_gain_reason = s_.force_gain_reason;
  st.feel = s_.derive_force_gain ? feelName(s_.feel) : "given";
  st.coupled = loop_.settings().pipeline.coupling.active();
  st.added_mass_kg = s_.loop.pipeline.coupling.added_mass_kg;
  const haptics::TickOutput latest = loop_.latest();
  st.hand_force_n = latest.commanded_n;
  st.probe_force_n = latest.sim_force_n;
  st.drag_n_s_m = latest.drag_n_s_m;
  st.guide_weight = latest.guide_weight;
  st.guide_force_n = latest.guide_n;
  st.guide_target_m = s_.loop.pipeline.map.positionToDomain(latest.guide_target_m);
  st.guide = loop_.settings().pipeline.guide;
  st.error = error();
  return st;
}

std::vector<haptics::TraceSample> HapticSession::drainTrace() {
  std::vector<haptics::TraceSample> out;
  std::lock_guard<std::mutex> lock(mutex_);  // one consumer at a time
  loop_.drainTrace(out);
  return out;
}

}  // namespace hf::session
