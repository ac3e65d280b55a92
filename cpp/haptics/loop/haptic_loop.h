// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// HapticLoop: the 1 kHz thread. Each period (absolute deadlines, SCHED_FIFO where permitted):
//   device.read() -> take the latest simulation force from `forces` (and the played pose from
//   the host, if any) -> ForcePipeline (predict, filter, map, guide, safety) -> publish the probe's
//   pose (domain frame: the grip's, or the played pose while the guide is engaged) to `poses`
//   -> device.writeForce().
// It takes no lock and never waits for the simulation, the GPU or Python: both mailboxes are
// lock-free, statistics and the trace are lock-free too. A device error (read or writeForce
// throws) ends the loop: it stops commanding force (one last zero is attempted) and error()
// says what happened. The host reads stats(), latest() and drainTrace() from any one thread.
#include <atomic>
#include <exception>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "haptics/devices/device.h"
#include "haptics/handoff/frames.h"
#include "haptics/handoff/mailbox.h"
#include "haptics/loop/sample_window.h"
#include "haptics/loop/trace_ring.h"
#include "haptics/rendering/force_pipeline.h"

namespace hf::haptics {

struct HapticLoopSettings {
  double rate_hz = 1000.0;             // loop rate, Hz (100 .. 10000)
  PipelineSettings pipeline;           // safety.max_force_n at most the device's maximum;
                                       // passivity.max_damping_n_s_m too (None: the device's)
  bool realtime = true;                // ask for SCHED_FIFO
  int realtime_priority = 80;          // 1 .. 99
  std::size_t trace_capacity = 0;      // records kept for drainTrace() (0: no trace)
  void validate() const;
};

// The virtual coupling as a loop on this device renders it: a stiffness or damping left at 0 takes
// its share of the device's stable limits (kCouplingStiffnessShare, kCouplingDampingShare); it
// renders where the result is active() (a device that reports no stiffness keeps the seed's rendering).
CouplingSettings couplingOn(CouplingSettings c, const DeviceInfo& device);

struct TraceSample {                   // one haptic period
  double time_s = 0.0;                 // monotonic clock
  glm::vec3 position_m{0.0f};          // device frame
  glm::vec3 sim_force_n{0.0f};         // fluid N
  glm::vec3 filtered_n{0.0f};          // device N, before safety
  glm::vec3 commanded_n{0.0f};         // device N
  glm::vec3 guide_n{0.0f};             // the playback guide's part of it, device N
  // The simulation step this period's force came from (zero before the first): the probe
  // velocity it used (fluid frame, m/s), its own time step (s) and when its pose was read
  // (monotonic clock), so a check can hold the engine's force against the motion it saw.
  glm::vec3 step_velocity_m_s{0.0f};
  double step_dt_s = 0.0;
  double step_pose_time_s = 0.0;
  float model_added_mass_kg = 0.0f;    // the local model's added mass in use (fluid kg; coupled only)
};

struct LoopStats {
  bool running = false;
  std::uint64_t ticks = 0;             // periods run
  double rate_hz = 0.0;                // 1 / mean period over the window
  Percentiles period_ms;               // measured periods
  Percentiles jitter_ms;               // |period - nominal period|
  Percentiles latency_ms;              // pose read -> first period using the force computed from it
  std::uint64_t skipped = 0;           // deadlines missed by a whole period
  std::uint64_t frames = 0;            // simulation force frames received
  std::uint64_t non_finite = 0;        // NaN/Inf forces zeroed by the safety stage
  std::uint64_t trace_dropped = 0;     // trace records lost (ring full)
  PassivityState passivity;            // the passivity observer/controller (passivity_controller.h)
  float max_damping_n_s_m = 0.0f;      // the controller's damping bound in use, N s/m (0: none, observed only)
  bool realtime = false;               // SCHED_FIFO granted
  std::string scheduling;              // "" or the warning about real-time priority
  std::string error;                   // "" or the device error that ended the loop
};

class HapticLoop {
 public:
  HapticLoop(DevicePtr device, Mailbox<PoseFrame>& poses, const Mailbox<ForceFrame>& forces,
             const HapticLoopSettings& settings);
  ~HapticLoop();  // stops and joins
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  // Starts the thread (once). Throws hf::Error if another loop (or a host call) holds the
  // device: the loop holds it (DeviceClaim) until its thread ends.
  void start();
  // Slews the force down to zero at the slew rate (max_force / slew_rate, at most
  // kMaxWindDownS = 2 s; those periods are in the trace), ends the thread, joins, and sends a
  // last zero. From any thread; concurrent calls take turns.
  void stop();
  void setEnabled(bool on);     // false: force slews down to zero; true: ramp in again
  // Haptic playback (playback_guide.h): the pose the host plays (domain frame, m and m/s), stamped
  // now; the loop carries it forward at its velocity, pulls the grip towards it and hands the
  // probe to it. releaseGuide(): let go (the guide fades out over its ramp). Any host thread; a
  // lock-free Mailbox write, never waiting on the loop.
  void setGuide(const glm::vec3& position_m, const glm::vec3& velocity_m_s);
  void releaseGuide();
  bool running() const { return running_.load(std::memory_order_acquire); }
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  std::string error() const;    // "" unless failed()
  // The device's exception that ended the loop (its own type, e.g. falcon::UsbUnplugged), or null.
  std::exception_ptr cause() const;
  LoopStats stats() const;
  TickOutput latest() const;    // the latest period's forces
  DeviceState latestState() const;
  std::size_t drainTrace(std::vector<TraceSample>& out) { return trace_.drain(out); }
  const HapticLoopSettings& settings() const { return s_; }

 private:
  void run();
  // One period: device.read() -> takeInputs -> ForcePipeline::tick -> the probe's pose to the
  // simulation -> device.writeForce() -> publish (stats, latest(), the trace).
  void tickOnce(double now_s, double dt_s, bool may_enable);  // may_enable false: stopping
  // The pipeline's input: the played pose from the host (device frame, inside the device's reach),
  // the newest simulation force (counting frames and their latency), this reading.
  TickInput takeInputs(double now_s, double dt_s, bool may_enable, const DeviceState& state);
  // The probe's pose for the simulation (domain frame): the grip's, or with the guide engaged
  // (weight w) the played pose, blended by w.
  PoseFrame probePose(const DeviceState& state, const TickOutput& out, double now_s) const;
  void publish(const DeviceState& state, const TickOutput& out, double now_s);

  DevicePtr device_;
  Mailbox<PoseFrame>& poses_;
  const Mailbox<ForceFrame>& forces_;
  HapticLoopSettings s_;
  ForcePipeline pipeline_;  // haptic thread only

  std::thread thread_;
  std::mutex thread_mutex_;  // start() and stop() from several host threads: one joins
  std::atomic<bool> stop_{false}, running_{false}, failed_{false}, enabled_{true}, realtime_{false};
  std::string error_;       // written once by the loop before failed_ is set
  std::exception_ptr cause_;  // the exception behind error_, written with it
  std::string scheduling_;  // written by the loop before sched_known_ is set
  std::atomic<bool> sched_known_{false};

  // Haptic-thread state.
  GuideTarget played_{}, last_played_{};  // the host's played pose (domain frame); the last active one
  ForceFrame force_{};
  bool have_force_ = false;
  std::uint64_t force_version_ = 0;

  // Published to the host.
  std::atomic<std::uint64_t> ticks_{0}, frames_{0};
  std::atomic<std::uint64_t> skipped_{0};
  SampleWindow<8192> periods_ms_;
  SampleWindow<2048> latencies_ms_;
  Mailbox<TickOutput> latest_;
  Mailbox<DeviceState> latest_state_;
  std::atomic<std::uint64_t> non_finite_{0};
  Mailbox<PassivityState> passivity_;
  Mailbox<GuideTarget> guide_;  // host -> haptic thread (domain frame)
  TraceRing<TraceSample> trace_;
  glm::vec3 reach_lo_m_, reach_hi_m_;  // the device's workspace (the guide's target stays inside)
};

}  // namespace hf::haptics
