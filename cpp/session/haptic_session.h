// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// HapticSession: a Simulation touched through a haptic Device. Three threads:
//   haptic thread (haptics::HapticLoop, 1 kHz): device -> pose mailbox; force mailbox ->
//     filter, map, safety -> device. It never waits on this object, the GPU or Python.
//   simulation thread (owned here, free-running): latest pose -> probe -> Simulation::step ->
//     force mailbox. A step takes as long as the GPU needs; the haptic thread does not notice.
//   host (Python, Blender): start/pause/resume/stop, stats(), latest(), drainTrace(),
//     fieldSnapshot(); none of these waits for a GPU step except stop(), which waits at most its
//     timeout. With snapshots on, the simulation thread reads the fields back right after its
//     step and publishes them (FieldSnapshot), so the host can draw them without the GPU.
// An error on either thread (device gone: zero at once; solver failure: slewed to zero) stops force output and is
// kept: error() returns it and stop() throws it after a clean shutdown: the device's own exception
// (its type kept, e.g. falcon::UsbUnplugged) or hf::Error for the simulation thread's.
#include <atomic>
#include <condition_variable>
#include <exception>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "haptics/devices/device.h"
#include "haptics/handoff/mailbox.h"
#include "haptics/loop/haptic_loop.h"
#include "obstacle/triangle_mesh.h"
#include "session/field_snapshot.h"

namespace hf::session {

class Simulation;
class SimulationClaim;

inline constexpr double kDefaultTraceS = 600.0;  // trace length the Python API keeps when asked, s

// What the hand feels of the fluid's force (with derive_force_gain): Amplified, the largest gain
// the rendering holds passively with its margin (rendering_limits.h), or Physical, 1:1 where that
// largest gain is at least 1 (a probe in water at a large workspace scale gets that gain instead).
enum class Feel { Amplified, Physical };
const char* feelName(Feel f);
Feel feelFromName(const std::string& name);  // "amplified" or "physical"; InvalidArgument otherwise

struct HapticSessionSettings {
  // The session fills loop.pipeline.map.offset_m, loop.pipeline.filter.max_cutoff_hz,
  // loop.pipeline.safety.max_force_n and loop.trace_capacity from the settings below (resolve());
  // the rest is used as set.
  haptics::HapticLoopSettings loop;
  // Domain position (m) of the device origin; none: the offset that puts the middle of the
  // device's workspace (DeviceInfo) at the domain's centre, for the map's scale.
  std::optional<glm::vec3> workspace_offset_m;
  // True: loop.pipeline.map.scale becomes the largest uniform scale at which the device's
  // workspace fits the domain (min over axes of domain edge / workspace edge), the axes' signs
  // kept; false: the scale is used as set.
  bool fit_workspace = false;
  // The low-pass cutoff is at most this fraction of the haptic rate (dimensionless, (0, 0.5]).
  double max_cutoff_per_rate = 0.2;
  // Keep a record of each haptic period for drainTrace(), trace_s seconds of them at the loop's rate.
  bool trace = false;
  double trace_s = kDefaultTraceS;
  // Bound on the commanded force (N), at most the device's maximum; none: that maximum. resolve()
  // writes it into loop.pipeline.safety.max_force_n.
  std::optional<float> max_force_n;
  // Field snapshots: none: off; 0: after every step; > 0: after the first step that ends at least
  // this long (s, wall time) after the previous snapshot. Each costs one density read-back (and
  // one temperature read-back with snapshot_temperature) on the simulation thread.
  std::optional<double> snapshot_interval_s;
  bool snapshot_temperature = false;
  // A sphere of this radius (m, >= one cell) becomes the probe; none: the simulation's current
  // probe (sphere or mesh, its orientation kept) is moved, or a 0.1 m sphere if it has none.
  std::optional<float> probe_radius_m;
  double sim_dt_s = 0.0;           // fixed simulation step, s (free-running); 0 = real time
  // Real time: each step advances the (smoothed) wall time since the last one, within
  // [min_sim_dt_s, max_sim_dt_s]; a step that finishes early waits for min_sim_dt_s of wall time.
  // The floor matters: a voxelized probe gives force impulses ~ 1/dt when it crosses cells.
  double min_sim_dt_s = 0.01;
  double max_sim_dt_s = 0.05;
  // True: loop.pipeline.map.force_gain is replaced by the gain the device can render for this
  // probe, fluid and workspace scale (haptics/rendering/rendering_limits.h); false: the given gain is used.
  bool derive_force_gain = true;
  // A given gain above the derived one (what the rendering holds passively) is refused unless
  // this is set: the user accepted that the rendering may then put energy into the hand.
  bool allow_unsafe_gain = false;
  Feel feel = Feel::Amplified;     // with derive_force_gain: amplified (derived) or physical (1)
  std::string force_gain_reason;   // set by the session: how the gain in use was chosen
  void validate() const;
  // These settings with the derived loop fields filled in for this domain and device; validates.
  HapticSessionSettings resolve(const glm::vec3& domain_origin_m, const glm::vec3& domain_size_m,
                                const haptics::DeviceInfo& device) const;
};

enum class SessionState { Idle, Running, Paused, Stopped, Failed };
const char* stateName(SessionState s);

struct HapticSessionStats {
  SessionState state = SessionState::Idle;
  haptics::LoopStats haptic;
  double sim_rate_hz = 0.0;        // smoothed simulation steps per second
  std::uint64_t sim_steps = 0;     // steps taken by this session
  double sim_step_ms = 0.0;        // host time of the latest step, ms
  double sim_dt_s = 0.0;           // time step of the latest step, s
  std::uint64_t snapshots = 0;     // field snapshots published
  double stale_after_s = 0.0;      // age at which the latest force starts fading (safety stage), s
  float force_gain = 0.0f;         // device N per fluid N in use
  std::string feel;                // "amplified", "physical" or "given"
  bool coupled = false;            // rendered through the virtual coupling (force at the haptic rate)
  double added_mass_kg = 0.0;      // the probe's added mass the local model renders (fluid kg)
  glm::vec3 hand_force_n{0.0f};    // the latest force on the hand (device N)
  glm::vec3 probe_force_n{0.0f};   // the latest force of the fluid on the probe (fluid N)
  glm::vec3 drag_n_s_m{0.0f};      // the local model's drag (fluid N s/m, <= 0)
  std::string force_gain_reason;   // how it was chosen
  // Haptic playback (setGuide): the guide's weight (0 off .. 1 engaged), its force on the hand
  // (device N), the played pose now (domain m) and the gains in use (resolved from the device).
  float guide_weight = 0.0f;
  glm::vec3 guide_force_n{0.0f};
  glm::vec3 guide_target_m{0.0f};
  haptics::GuideSettings guide;
  std::string error;               // "" or the first error
};

class HapticSession {
 public:
  // The simulation must outlive the session (Python keeps it alive). Throws InvalidArgument
  // for bad settings (probe radius against the grid included) before anything starts, and
  // hf::Error while another session drives the simulation.
  HapticSession(Simulation& sim, haptics::DevicePtr device, const HapticSessionSettings& settings);
  ~HapticSession();  // stops and joins both threads; never throws
  HapticSession(const HapticSession&) = delete;
  HapticSession& operator=(const HapticSession&) = delete;

  // Starts both threads (once). Throws hf::Error if another running session drives the same
  // Simulation or device: the session holds both (SimulationClaim, DeviceClaim) until stop().
  void start();
  void pause();   // force slews to zero (max_force / slew_rate), simulation holds after its current step
  void resume();  // simulation steps again, force ramps in again
  // Force slewed to zero at the slew rate (at most haptics::kMaxWindDownS = 2 s) and the haptic thread joined; then waits up to timeout_s for the
  // simulation's current step. Throws hf::Error if that step is still running (call again),
  // or the error that ended the session (after the threads are down). Callable from any host
  // thread; concurrent calls take turns.
  void stop(double timeout_s = 10.0);

  // Failed as soon as either thread has failed; Stopped once stop() has ended force output
  // (the simulation's last step may still be finishing if stop() timed out).
  SessionState state() const;
  HapticSessionStats stats() const;
  haptics::TickOutput latest() const { return loop_.latest(); }
  haptics::DeviceState latestState() const { return loop_.latestState(); }
  std::string error() const;
  std::vector<haptics::TraceSample> drainTrace();
  // The newest field snapshot, or null (snapshots off, or none published yet). Never waits for
  // the GPU: it copies a pointer under a lock the simulation thread holds only to swap it.
  std::shared_ptr<const FieldSnapshot> fieldSnapshot() const;
  const HapticSessionSettings& settings() const { return s_; }
  // The device's workspace mapped into the domain (world m, minimum and maximum corners): where
  // the probe can go, before the simulation keeps it one cell from every wall.
  std::pair<glm::vec3, glm::vec3> workspaceBox() const;
  const haptics::DevicePtr& device() const { return device_; }

  // Haptic playback: the pose the host plays (the keys the timeline plays; domain frame, world m,
  // and its velocity in m/s). The fluid's probe takes it instead of the grip's, and a guide
  // (haptics/rendering/playback_guide.h) pulls the grip along it at the haptic rate so the hand feels the
  // played motion (with the fluid's force on the played probe). Call it at each host tick; a pose
  // not renewed within guide_stale lets go. The grip and the probe are handed over within
  // guide_ramp (no step). Throws InvalidArgument naming position or velocity (not finite; a speed
  // above the simulation's probe limit). Never waits: a lock-free write the haptic thread reads.
  void setGuide(const glm::vec3& position_m, const glm::vec3& velocity_m_s);
  // Lets go of the played pose: the guide fades out over guide_ramp, the probe goes back to the grip.
  void releaseGuide() { loop_.releaseGuide(); }

  // The probe pose for a published device pose (the one place the probe is placed): the probe's
  // transform at the start with its translation at the mapped device position, kept inside the
  // region the simulation accepts (one cell of fluid from every wall); the velocity is zero
  // along an axis held at a wall. A pose with an orientation (a 6-DoF host device) turns the
  // probe: rotation = the pose's, scale = the start's (the transform's rotation taken out by
  // probeRotation()), with its angular velocity; a turn whose world box cannot keep one cell from
  // every wall keeps the starting rotation instead. Applied with Simulation::setProbePose.
  obstacle::RigidPose poseFor(const haptics::PoseFrame& pose) const;
  // Where the engine puts the probe's origin (world m) for a device position (device frame, m):
  // the session's workspace map, then poseFor()'s hold one cell from every wall. The host draws
  // and records the probe there instead of mapping the device's position itself.
  glm::vec3 probeOriginFor(const glm::vec3& device_position_m) const;

  // The rotation part of a probe transform (local -> world, may scale or mirror): Gram-Schmidt
  // on its columns x, then y, with z = x cross y, so always a proper rotation; the rest
  // (rotation^T * transform) is the probe's local scale, negative on z for a mirrored one. A
  // host device pushes this rotation as its orientation (Python: HapticSession.probe_rotation).
  static glm::mat3 probeRotation(const glm::mat4& transform);

 private:
  void simLoop();
  void publishSnapshot(double now_s);  // simulation thread
  void fail(const std::string& message, std::exception_ptr cause = nullptr);
  void joinAll();

  Simulation& sim_;
  haptics::DevicePtr device_;
  HapticSessionSettings s_;
  haptics::Mailbox<haptics::PoseFrame> poses_;
  haptics::Mailbox<haptics::ForceFrame> forces_;
  haptics::HapticLoop loop_;
  glm::mat4 base_transform_{1.0f};                 // the probe's orientation (and scale)
  glm::vec3 probe_lo_m_{0.0f}, probe_hi_m_{0.0f};  // where the probe's origin may go
  // Mesh probes: the extent and the local scale (probeRotation's rest) for turned poses; the
  // walls the probe's world box must keep clear of (one cell in).
  bool mesh_probe_ = false;
  obstacle::MeshExtent extent_;
  glm::mat3 local_scale_{1.0f};
  glm::vec3 wall_lo_m_{0.0f}, wall_hi_m_{0.0f};

  std::atomic<SessionState> state_{SessionState::Idle};
  std::unique_ptr<SimulationClaim> sim_claim_;  // start() .. the simulation thread joined
  std::thread sim_thread_;
  std::mutex stop_mutex_;              // one stop()/joinAll() at a time (host threads, atexit)
  mutable std::mutex mutex_;           // guards the fields below (never taken by the haptic thread)
  std::condition_variable cv_;
  bool stop_requested_ = false;
  bool paused_ = false;
  bool sim_done_ = false;
  std::string error_;
  std::exception_ptr cause_;  // the device's own exception when the haptic loop failed, else null
  bool error_raised_ = false;

  std::atomic<double> sim_rate_hz_{0.0};
  std::atomic<std::uint64_t> sim_steps_{0};
  std::atomic<double> sim_step_ms_{0.0};
  std::atomic<double> sim_dt_s_{0.0};

  mutable std::mutex snapshot_mutex_;  // guards snapshot_ (held only to swap or copy the pointer)
  std::shared_ptr<const FieldSnapshot> snapshot_;
  std::atomic<std::uint64_t> snapshots_{0};
  std::uint64_t snapshot_sequence_ = 0;  // simulation thread only
  double last_snapshot_s_ = -1.0;        // simulation thread only
};

}  // namespace hf::session
