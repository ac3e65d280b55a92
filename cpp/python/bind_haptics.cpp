// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core haptics: Device (+ DeviceInfo, DeviceState), the virtual devices' factories
// and HapticSession. Argument conversion, docstrings and GIL release only.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "haptics/devices/device.h"
#include "haptics/devices/device_claim.h"
#include "haptics/devices/host_device.h"
#include "haptics/devices/null_device.h"
#include "haptics/devices/scripted_device.h"
#include "haptics/handoff/clock.h"
#include "haptics/rendering/passivity_controller.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/convert_mesh.h"
#include "python/named_args.h"
#include "python/settings_class.h"
#include "session/field_snapshot.h"
#include "session/haptic_session.h"
#include "session/simulation.h"

namespace py = pybind11;

namespace hf::python {
namespace {

using haptics::Device;
using haptics::DeviceInfo;
using haptics::DevicePtr;
using haptics::DeviceState;
using session::HapticSession;
using Vec3 = std::array<float, 3>;

py::dict percentiles(py::dict d, const std::string& name, const haptics::Percentiles& p) {
  d[py::str(name + "_p50_ms")] = p.p50;
  d[py::str(name + "_p99_ms")] = p.p99;
  d[py::str(name + "_max_ms")] = p.max;
  d[py::str(name + "_mean_ms")] = p.mean;
  return d;
}

py::dict statsDict(const session::HapticSessionStats& s) {
  py::dict d;
  d["state"] = session::stateName(s.state);
  d["haptic_rate_hz"] = s.haptic.rate_hz;
  d["ticks"] = s.haptic.ticks;
  percentiles(d, "period", s.haptic.period_ms);
  percentiles(d, "jitter", s.haptic.jitter_ms);
  percentiles(d, "latency", s.haptic.latency_ms);
  d["latency_samples"] = s.haptic.latency_ms.count;
  d["skipped_periods"] = s.haptic.skipped;
  d["force_frames"] = s.haptic.frames;
  d["non_finite_forces"] = s.haptic.non_finite;
  d["trace_dropped"] = s.haptic.trace_dropped;
  d["realtime"] = s.haptic.realtime;
  d["scheduling"] = s.haptic.scheduling;
  d["sim_rate_hz"] = s.sim_rate_hz;
  d["sim_steps"] = s.sim_steps;
  d["sim_step_ms"] = s.sim_step_ms;
  d["sim_dt"] = s.sim_dt_s;
  d["snapshots"] = s.snapshots;
  d["stale_after"] = s.stale_after_s;
  d["force_gain"] = s.force_gain;
  d["force_gain_reason"] = s.force_gain_reason;
  d["feel"] = s.feel;
  d["coupling"] = s.coupled;
  d["added_mass"] = s.added_mass_kg;
  d["hand_force"] = vec3Array(s.hand_force_n);
  d["probe_force"] = vec3Array(s.probe_force_n);
  d["model_drag"] = vec3Array(s.drag_n_s_m);
  d["guide_weight"] = s.guide_weight;
  d["guide_force"] = vec3Array(s.guide_force_n);
  d["guide_target"] = vec3Array(s.guide_target_m);
  d["guide_stiffness"] = s.guide.stiffness_n_m;
  d["guide_damping"] = s.guide.damping_n_s_m;
  d["guide_max_force"] = s.guide.max_force_n;
  const haptics::PassivityState& p = s.haptic.passivity;
  d["passivity_energy"] = p.energy_j;
  d["passivity_delivered"] = p.delivered_j;
  d["passivity_dissipated"] = p.dissipated_j;
  d["passivity_alpha"] = p.alpha_n_s_m;
  d["passivity_active_ticks"] = p.active;
  d["passivity_resets"] = p.resets;
  d["passivity_turn_ticks"] = p.turn_ticks;
  d["passivity_max_damping"] = s.haptic.max_damping_n_s_m;
  d["error"] = s.error.empty() ? py::object(py::none()) : py::object(py::str(s.error));
  return d;
}

py::array_t<float> vec3Rows(const std::vector<haptics::TraceSample>& t, glm::vec3 haptics::TraceSample::*member) {
  py::array_t<float> a({static_cast<py::ssize_t>(t.size()), py::ssize_t{3}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < t.size(); ++i) {
    for (int k = 0; k < 3; ++k) r(static_cast<py::ssize_t>(i), k) = (t[i].*member)[k];
  }
  return a;
}

template <class T>
py::array_t<double> scalarRows(const std::vector<haptics::TraceSample>& t, T haptics::TraceSample::*member) {
  py::array_t<double> a(static_cast<py::ssize_t>(t.size()));
  auto r = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < t.size(); ++i) r(static_cast<py::ssize_t>(i)) = static_cast<double>(t[i].*member);
  return a;
}

const char* kSessionDoc = R"doc(
A Simulation touched through a haptic Device: a 1 kHz haptic thread and a free-running
simulation thread, started by start() (or by entering a `with` block) and ended by stop().

Per haptic period: device pose -> (workspace map) -> probe pose for the simulation thread;
latest simulation force -> [prediction] -> low-pass (cutoff = bandwidth_ratio x measured
simulation rate) -> force_gain -> passivity controller -> safety (NaN guard, homing gate,
stale-force fade, ramp-in, max_force clamp, slew_rate limit) -> device. With the coupling (the
default on a device that reports its limits) each step identifies a local model of the fluid's
force and a proxy carrying it is coupled to the hand at the haptic rate (see coupling).

simulation: the Simulation to drive (kept alive by the session); the session steps it
  continuously and its probe follows the device.
device: a Device (null_device(), scripted_device(), host_device(), a Falcon ...).
settings: a HapticSessionSettings, or None for the engine's defaults; keywords set the settings
  of the same names on a copy of it: HapticSession(sim, device, probe_radius=0.08).
  HapticSessionSettings documents each (workspace map, force gain, filter, passivity, safety,
  rates, trace, snapshots).
)doc";

// A snapshot field as a read-only array [x, y, z] (x fastest) that keeps the snapshot alive.
py::array_t<float> snapshotArray(const std::shared_ptr<const session::FieldSnapshot>& snap,
                                 const std::vector<float>& field) {
  auto* owner = new std::shared_ptr<const session::FieldSnapshot>(snap);
  py::capsule keep(owner, [](void* p) { delete static_cast<std::shared_ptr<const session::FieldSnapshot>*>(p); });
  const glm::ivec3 n = snap->resolution;
  const py::ssize_t b = static_cast<py::ssize_t>(sizeof(float));
  py::array_t<float> a({py::ssize_t{n.x}, py::ssize_t{n.y}, py::ssize_t{n.z}}, {b, b * n.x, b * n.x * n.y},
                       field.data(), keep);
  a.attr("setflags")(py::arg("write") = false);  // the snapshot is shared: nobody writes into it
  return a;
}

// The devices: DeviceInfo, DeviceState, Device, the virtual devices' factories and the session's
// defaults.
void addDeviceTypes(py::module_& m) {
  py::class_<DeviceInfo>(m, "DeviceInfo", "What a haptic device is and can do (SI units).")
      .def_readonly("name", &DeviceInfo::name)
      .def_readonly("kind", &DeviceInfo::kind, "'falcon', 'simulated_falcon', 'scripted', 'host' or 'null'.")
      .def_readonly("serial", &DeviceInfo::serial, "Serial number; '' if none.")
      .def_property_readonly("workspace_min", [](const DeviceInfo& i) { return vec3Array(i.workspace_min_m); },
                             "Reachable box, minimum corner (m, device frame).")
      .def_property_readonly("workspace_max", [](const DeviceInfo& i) { return vec3Array(i.workspace_max_m); },
                             "Reachable box, maximum corner (m, device frame).")
      .def_readonly("max_force", &DeviceInfo::max_force_n, "Largest force the device is commanded (N).")
      .def_readonly("max_stiffness", &DeviceInfo::max_stiffness_n_m,
                    "Largest stiffness the device renders stably (N/m; 0: not reported). Bounds the\n"
                    "default force gain.")
      .def_readonly("max_damping", &DeviceInfo::max_damping_n_s_m,
                    "Largest damping the device renders stably (N s/m; 0: not reported). Bounds the\n"
                    "default force gain and the passivity controller's damper.")
      .def_readonly("position_resolution", &DeviceInfo::position_resolution_m,
                    "Spread of a position reading's quantization error per axis (m; 0: exact or not\n"
                    "reported). The grip's velocity is fitted to the readings within it.")
      .def("__repr__", [](const DeviceInfo& i) {
        return "DeviceInfo(name='" + i.name + "', kind='" + i.kind + "', max_force=" + std::to_string(i.max_force_n) +
               " N)";
      });

  py::class_<DeviceState>(m, "DeviceState", "One reading of a haptic device (device frame, SI units).")
      .def_property_readonly("position", [](const DeviceState& s) { return vec3Array(s.position_m); },
                             "End effector position (m).")
      .def_property_readonly("velocity", [](const DeviceState& s) { return vec3Array(s.velocity_m_s); },
                             "End effector velocity (m/s).")
      .def_readonly("buttons", &DeviceState::buttons, "Bit i set: button i pressed.")
      .def_readonly("homed", &DeviceState::homed, "False: no force may be commanded yet.")
      .def_readonly("time", &DeviceState::time_s, "Time of the reading (s, time.monotonic() clock).")
      .def_property_readonly(
          "orientation",
          [](const DeviceState& s) -> py::object {
            if (!s.has_orientation) return py::none();
            return py::make_tuple(s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z);
          },
          "The handle's rotation as a unit quaternion (w, x, y, z), or None for a 3-DoF device.")
      .def_property_readonly("angular_velocity", [](const DeviceState& s) { return vec3Array(s.angular_velocity_rad_s); },
                             "Angular velocity (rad/s, device frame; zeros for a 3-DoF device).")
      .def("__repr__", [](const DeviceState& s) {
        return "DeviceState(position=(" + std::to_string(s.position_m.x) + ", " + std::to_string(s.position_m.y) +
               ", " + std::to_string(s.position_m.z) + ") m, homed=" + (s.homed ? "True" : "False") + ")";
      });

  py::class_<Device, DevicePtr> device(m, "Device", R"doc(
A haptic device (Falcon, simulated Falcon, scripted, host-driven or null). While a
HapticSession drives it, read() and write_force() raise HapticFluidError, and a second
session on it fails to start; close() still stops it (the session then fails with an error).
)doc");
  device.def("info", &Device::info, "A DeviceInfo: name, kind, workspace, max_force ...")
      .def(
          "read",
          [](Device& d) {
            const haptics::DeviceClaim claim(d, "read() it");
            return d.read();
          },
          py::call_guard<py::gil_scoped_release>(),
          "The latest DeviceState. Raises HapticFluidError if the device is gone or closed, or while\n"
          "a HapticSession drives it.")
      .def("close", &Device::close, py::call_guard<py::gil_scoped_release>(),
           "Zero force and release the device (idempotent).")
      .def("__enter__", [](const DevicePtr& d) { return d; })
      .def("__exit__", [](Device& d, py::args) {
        py::gil_scoped_release release;
        d.close();
      });
  defNamed(
      device, "write_force",
      [](Device& d, const Vec3& f) {
        const haptics::DeviceClaim claim(d, "write_force() to it");
        d.writeForce(toVec3(f));
      },
      py::arg("force"), py::call_guard<py::gil_scoped_release>(),
      "Command a force (N, device frame). No safety stage here: a HapticSession adds one.\n"
      "Raises HapticFluidError while a HapticSession drives the device (its safety stage owns\n"
      "the output).");

  py::class_<haptics::ScriptedDevice, Device, std::shared_ptr<haptics::ScriptedDevice>> scripted(
      m, "ScriptedDevice", "A handle following timed waypoints; made by scripted_device().");
  scripted.def_property_readonly("duration", &haptics::ScriptedDevice::durationS, "Last time - first time (s).")
      .def_property_readonly("loops", &haptics::ScriptedDevice::loops, "True: starts over at the end.")
      .def_property_readonly("last_force",
                             [](const haptics::ScriptedDevice& d) { return vec3Array(d.lastForce()); },
                             "The latest force commanded to it (N).");
  defNamed(scripted, "state_at", &haptics::ScriptedDevice::stateAt, py::arg("t"),
           "The DeviceState t seconds after the script started (no clock involved).");

  py::class_<haptics::HostDevice, Device, std::shared_ptr<haptics::HostDevice>> host(
      m, "HostDevice", "A handle whose pose the host pushes each frame; made by host_device().");
  defNamed(
          host, "push_pose",
          [](haptics::HostDevice& d, const Vec3& position, std::optional<double> time,
             std::optional<std::array<float, 4>> orientation) {
            const double t = time ? *time : haptics::monotonicNowS();
            if (orientation) {
              const auto& q = *orientation;
              d.pushPose(toVec3(position), glm::quat(q[0], q[1], q[2], q[3]), t);
            } else {
              d.pushPose(toVec3(position), t);
            }
          },
          py::arg("position"), py::arg("time") = py::none(), py::arg("orientation") = py::none(),
          py::call_guard<py::gil_scoped_release>(),
          "Set the handle's position (m, device frame) sampled at `time` (s, increasing; default now\n"
          "on time.monotonic()). The velocity is estimated from successive pushes. orientation: None\n"
          "(a 3-DoF handle) or the rotation as a quaternion (w, x, y, z), normalised here: the\n"
          "session's probe then turns with it (its scale stays the one it started with) and its\n"
          "angular velocity is estimated from successive pushes. Never blocks the haptic thread.");
  defNamed(host, "state_after", &haptics::HostDevice::stateAfter, py::arg("elapsed"),
           "The DeviceState `elapsed` seconds after the latest push arrived (no clock involved).");
  host.def_property_readonly("pushes", &haptics::HostDevice::pushes, "Poses pushed so far.")
      .def_property_readonly("last_force", [](const haptics::HostDevice& d) { return vec3Array(d.lastForce()); },
                             "The latest force commanded to it (N), e.g. to show in the viewport.");

  defNamed(
      m, "null_device", [](float max_force) -> DevicePtr { return std::make_shared<haptics::NullDevice>(max_force); },
      py::arg("max_force") = 10.0f,
      "A device that rests at the workspace origin, is homed and discards forces (max_force in N).");
  defNamed(
      m, "scripted_device",
      [](std::vector<double> times, std::vector<Vec3> positions, bool loop, float max_force) {
        std::vector<glm::vec3> p;
        p.reserve(positions.size());
        for (const auto& v : positions) p.push_back(toVec3(v));
        return std::make_shared<haptics::ScriptedDevice>(std::move(times), std::move(p), loop, max_force);
      },
      py::arg("times"), py::arg("positions"), py::arg("loop") = false, py::arg("max_force") = 10.0f,
      "A device following waypoints: times (s, strictly increasing), positions (m, device frame,\n"
      "one (x, y, z) per time), linearly interpolated; at the end it holds the last one or, with\n"
      "loop=True, starts over. Time starts at its first read. max_force in N.");
  defNamed(
      m, "scripted_device_from_csv",
      [](const std::string& path, bool loop, float max_force) {
        return haptics::ScriptedDevice::fromCsv(pathArg(path, "path"), loop, max_force);
      },
      py::arg("path"), py::arg("loop") = false,
        py::arg("max_force") = 10.0f,
        "scripted_device() from a CSV file of t,x,y,z rows (s, m); '#' comments and a header line\n"
        "are skipped.");
  defNamed(
      m, "host_device",
      [](float max_force, bool extrapolate) { return std::make_shared<haptics::HostDevice>(max_force, extrapolate); },
      py::arg("max_force") = 10.0f, py::arg("extrapolate") = true,
      "A device driven by the host: call push_pose() each frame (from any thread). With\n"
      "extrapolate=True the 1 kHz loop carries the pose along the estimated velocity for up to one\n"
      "push interval. Not homed (no force) until the first push. max_force in N.");

  m.def(
      "haptic_session_defaults",
      [m]() { return m.attr("HapticSessionSettings")().attr("to_dict")(); },
      "The HapticSession's default settings by name (SI units): HapticSessionSettings().to_dict().");

}

// What a running session reports: state, error, stats, the latest tick, its trace and snapshots,
// where the engine puts the probe and the workspace.
void addSessionReadings(py::class_<HapticSession>& c) {
  c.def_property_readonly("state", [](const HapticSession& s) { return session::stateName(s.state()); },
                          "'idle', 'running', 'paused', 'stopped' (force output ended, even if stop() timed out\n"
                          "waiting for the last simulation step) or 'failed'.");
  c.def_property_readonly(
      "error",
      [](const HapticSession& s) -> py::object {
        const std::string e = s.error();
        return e.empty() ? py::object(py::none()) : py::object(py::str(e));
      },
      "The error that ended the session (device gone, solver failure), or None.");
  c.def("stats", [](const HapticSession& s) {
          FlushLogAfter flush;  // what the session's threads queued so far
          return statsDict(s.stats());
        },
        "A dict: state, haptic_rate_hz, period/jitter/latency p50, p99, max and mean (ms), ticks,\n"
        "skipped_periods, force_frames, sim_rate_hz, sim_steps, sim_step_ms, sim_dt (s), stale_after\n"
        "(s: the age at which the latest force starts fading, from the measured simulation rate), realtime,\n"
        "scheduling (warning or ''), error (or None), force_gain and force_gain_reason (the gain in\n"
        "use and how it was chosen), and the passivity controller's state since its last reset:\n"
        "passivity_energy (J, the observer: > 0 means the loop made net energy), passivity_delivered\n"
        "(J, plain sum of the energy delivered to the hand, F . dx), passivity_dissipated (J, removed\n"
        "by the damper), passivity_alpha (N s/m, the latest damping), passivity_active_ticks,\n"
        "passivity_turn_ticks (of those, periods that eased a force against the motion before the\n"
        "hand turns), passivity_resets, passivity_max_damping (N s/m, its bound). Latency: device read -> the\n"
        "first haptic period that uses the force computed from that pose. Haptic playback (set_guide):\n"
        "guide_weight (0 off .. 1 engaged), guide_force (device N), guide_target (the played pose now, world m,\n"
        "inside the device's reach), guide_stiffness (N/m), guide_damping (N s/m), guide_max_force (N) in use.");
  c.def_property_readonly(
      "latest_force", [](const HapticSession& s) { return vec3Array(s.latest().commanded_n); },
      "The force commanded to the device in the latest haptic period (N, device frame).");
  c.def(
      "latest",
      [](const HapticSession& s) {
        const haptics::TickOutput o = s.latest();
        py::dict d;
        d["sim_force"] = vec3Array(o.sim_force_n);
        d["predicted_force"] = vec3Array(o.predicted_n);
        d["filtered_force"] = vec3Array(o.filtered_n);
        d["passive_force"] = vec3Array(o.passive_n);
        d["damping"] = o.damping_n_s_m;
        d["commanded_force"] = vec3Array(o.commanded_n);
        d["commanded_force_world"] = vec3Array(o.commanded_domain_n);
        d["cutoff_hz"] = o.cutoff_hz;
        d["force_age"] = o.force_age_s;
        d["stale_after"] = o.stale_after_s;
        d["guide_force"] = vec3Array(o.guide_n);
        d["guide_weight"] = o.guide_weight;
        d["guide_target"] = vec3Array(o.guide_target_m);
        d["grip"] = vec3Array(o.grip_m);
        const DeviceState state = s.latestState();
        d["position"] = vec3Array(state.position_m);
        d["homed"] = state.homed;
        d["buttons"] = state.buttons;
        return d;
      },
      "The latest haptic period: sim_force, predicted_force (fluid N), filtered_force, passive_force\n"
      "(after the passivity controller), commanded_force (device N, device axes), commanded_force_world (the\n"
      "same newtons in world axes: an axis the workspace map mirrors is flipped back), damping (N s/m), cutoff_hz,\n"
      "force_age (s), stale_after (s: the age at which that force starts fading), guide_force (device N, the\n"
      "playback guide's part of commanded_force), guide_weight (0 off .. 1 engaged), guide_target (the played pose\n"
      "this period, device frame, m; stats() gives it in world m) and grip (the device position this period's\n"
      "forces came from, device frame, m): all of one period. position (m, device frame), homed, buttons (bit i:\n"
      "button i) of the device's latest reading (it may be a period newer).");
  c.def(
      "trace",
      [](HapticSession& s) {
        std::vector<haptics::TraceSample> t;
        {
          py::gil_scoped_release release;
          t = s.drainTrace();
        }
        py::array_t<double> time(static_cast<py::ssize_t>(t.size()));
        auto tr = time.mutable_unchecked<1>();
        for (std::size_t i = 0; i < t.size(); ++i) tr(static_cast<py::ssize_t>(i)) = t[i].time_s;
        py::dict d;
        d["time"] = time;
        d["position"] = vec3Rows(t, &haptics::TraceSample::position_m);
        d["sim_force"] = vec3Rows(t, &haptics::TraceSample::sim_force_n);
        d["filtered_force"] = vec3Rows(t, &haptics::TraceSample::filtered_n);
        d["commanded_force"] = vec3Rows(t, &haptics::TraceSample::commanded_n);
        d["step_velocity"] = vec3Rows(t, &haptics::TraceSample::step_velocity_m_s);
        d["step_dt"] = scalarRows(t, &haptics::TraceSample::step_dt_s);
        d["step_pose_time"] = scalarRows(t, &haptics::TraceSample::step_pose_time_s);
        d["model_added_mass"] = scalarRows(t, &haptics::TraceSample::model_added_mass_kg);
        return d;
      },
      "Hand over the haptic periods recorded since the last call (needs trace=True): a dict of\n"
      "arrays time (s, monotonic clock), position (m, device frame), sim_force (fluid N),\n"
      "filtered_force and commanded_force (device N), one row per period; and of the simulation step\n"
      "that force came from, step_velocity (the probe velocity it used, fluid m/s), step_dt (its\n"
      "time step, s) and step_pose_time (when its pose was read, monotonic s; 0 before the first\n"
      "step), and model_added_mass (the local model's added mass in use, fluid kg; 0 uncoupled).");
  c.def_property_readonly("device", [](const HapticSession& s) { return s.device(); }, "The Device it drives.");
  c.def(
      "snapshot",
      [](const HapticSession& s) -> py::object {
        std::shared_ptr<const session::FieldSnapshot> snap;
        {
          py::gil_scoped_release release;
          snap = s.fieldSnapshot();
        }
        if (!snap) return py::none();
        py::dict d;
        d["sequence"] = snap->sequence;
        d["time"] = snap->time_s;
        d["steps"] = snap->steps;
        d["resolution"] = py::make_tuple(snap->resolution.x, snap->resolution.y, snap->resolution.z);
        d["density"] = snapshotArray(snap, snap->density);
        d["temperature"] = snap->temperature.empty() ? py::object(py::none())
                                                     : py::object(snapshotArray(snap, snap->temperature));
        return d;
      },
      "The newest field snapshot (needs snapshot= at construction), or None before the first one.\n"
      "Never waits for the GPU: the simulation thread read the fields back right after its step.\n"
      "A dict: sequence (1, 2, ...: a new number means new fields), time (simulation s), steps,\n"
      "resolution, density (read-only float32 array [x, y, z], no copy), temperature (K above\n"
      "ambient, the same shape; None unless snapshot_temperature=True).");
  c.def_property_readonly(
      "workspace_offset", [](const HapticSession& s) { return vec3Array(s.settings().loop.pipeline.map.offset_m); },
      "Domain position of the device origin in use (m): the given offset or the centred default.");
  c.def_property_readonly(
      "workspace_scale", [](const HapticSession& s) { return vec3Array(s.settings().loop.pipeline.map.scale); },
      "Domain metres per device metre, per axis (the fitted one with fit_workspace).");
  defNamed(
      c, "probe_origin",
      [](const HapticSession& s, const py::array_t<float, py::array::c_style | py::array::forcecast>& positions) {
        if (positions.ndim() < 1 || positions.shape(positions.ndim() - 1) != 3 || positions.ndim() > 2) {
          throw InvalidArgument("probe_origin: positions must be (3,) or (N, 3) device-frame metres");
        }
        py::array_t<float> out(std::vector<py::ssize_t>(positions.shape(), positions.shape() + positions.ndim()));
        const float* in = positions.data();
        float* o = out.mutable_data();
        for (py::ssize_t i = 0; i < positions.size() / 3; ++i) {
          const glm::vec3 w = s.probeOriginFor(glm::vec3(in[3 * i], in[3 * i + 1], in[3 * i + 2]));
          for (int k = 0; k < 3; ++k) o[3 * i + k] = w[k];
        }
        return out;
      },
      py::arg("positions"),
      "Where the engine puts the probe's origin (world m) for device positions ((3,) or (N, 3),\n"
      "device frame, m): the workspace map, then the hold one cell from every wall. Draw and record\n"
      "the probe there.");
  c.def_static(
      "probe_rotation",
      [](const py::object& transform) {
        const glm::quat q = glm::quat_cast(HapticSession::probeRotation(toTransform(transform)));
        return py::make_tuple(q.w, q.x, q.y, q.z);
      },
      py::arg("transform"),
      "The rotation the engine takes from a probe's transform (4x4 local -> world, rows, m; may\n"
      "scale or mirror) as a quaternion (w, x, y, z): Gram-Schmidt on its x, then y column, z = x\n"
      "cross y; the rest is the probe's scale. A host device pushes this as the pose's orientation.");
  c.def_property_readonly(
      "workspace_box",
      [](const HapticSession& s) {
        const auto [lo, hi] = s.workspaceBox();
        return py::make_tuple(vec3Array(lo), vec3Array(hi));
      },
      "The device's workspace in the domain, (minimum corner, maximum corner) in world m: where the\n"
      "probe can go (the simulation keeps it one cell from every wall).");
}

}  // namespace

void addHaptics(py::module_& m) {
  addDeviceTypes(m);
  py::class_<HapticSession> c(m, "HapticSession", kSessionDoc);
  defInitNamed(
      c,
      [](session::Simulation& sim, DevicePtr device, const py::object& settings, const py::kwargs& kwargs) {
        const auto s = settingsWithKeywords<session::HapticSessionSettings>(settings, kwargs, "HapticSession");
        return std::make_unique<HapticSession>(sim, std::move(device), s);
      },
      py::arg("simulation"), py::arg("device"), py::arg("settings") = py::none(), py::keep_alive<1, 2>());
  c.def_property_readonly("settings", [](const HapticSession& s) { return s.settings(); },
                          "The HapticSessionSettings in use (a copy; force_gain None when derived: stats() has it).");
  // (Sessions still running when the interpreter ends are stopped by hapticfluid/_lifetime.py.)
  c.def("start", &HapticSession::start, py::call_guard<py::gil_scoped_release>(),
        "Start the haptic and simulation threads (once). Returns at once.");
  c.def("pause", &HapticSession::pause, py::call_guard<py::gil_scoped_release>(),
        "Force down to zero at slew_rate (8 N at 200 N/s: 40 ms); the simulation holds after its\n"
        "current step.");
  c.def("resume", &HapticSession::resume, py::call_guard<py::gil_scoped_release>(),
        "Step again; the force ramps in again over ramp_time.");
  defNamed(c, "stop", [](HapticSession& s, double timeout) {
          FlushLogAfter flush;  // what the session's threads queued (hapticfluid.haptics, .fluid, ...)
          py::gil_scoped_release release;
          s.stop(timeout);
        }, py::arg("timeout") = 10.0,
        "Force down to zero at slew_rate (max_force / slew_rate, at most 2 s) and both threads ended: waits at most\n"
        "`timeout` s for the simulation's current step (HapticFluidError if it is still running:\n"
        "call again). Raises the error that ended the session, if any (once), as HapticFluidError.\n"
        "Any thread may call it; concurrent calls take turns.");
  defNamed(
      c, "set_guide",
      [](HapticSession& s, const Vec3& position, const Vec3& velocity) {
        py::gil_scoped_release release;
        s.setGuide(toVec3(position), toVec3(velocity));
      },
      py::arg("position"), py::arg("velocity") = Vec3{0.0f, 0.0f, 0.0f},
      "Haptic playback: the pose the timeline plays (position: world m; velocity: m/s). The fluid's\n"
      "probe takes it instead of the grip's, and a spring-damper guide (guide_stiffness, guide_damping,\n"
      "at most guide_max_force) pulls the grip along it at 1 kHz, so the hand feels the played motion and\n"
      "the fluid's force on it; the hand can resist. Call at every host tick: the haptic thread carries\n"
      "it forward at its velocity, and lets go of one not renewed within guide_stale. Engaging and letting\n"
      "go fade over guide_ramp. InvalidArgumentError names position or velocity. Never waits.");
  c.def("release_guide", &HapticSession::releaseGuide, py::call_guard<py::gil_scoped_release>(),
        "Let go of the played pose: the guide fades out over guide_ramp and the probe goes back to the grip.");
  addSessionReadings(c);
  c.def("__enter__", [](const py::object& self) {
    auto& s = self.cast<HapticSession&>();
    if (s.state() == session::SessionState::Idle) {
      py::gil_scoped_release release;
      s.start();
    }
    return self;
  }, "Starts the session if it has not started.");
  c.def("__exit__", [](HapticSession& s, const py::object& exc_type, const py::object&, const py::object&) {
    FlushLogAfter flush;
    py::gil_scoped_release release;
    if (!exc_type.is_none()) {
      try {
        s.stop();
      } catch (const Error&) {  // the exception already leaving the block is the one to see
      }
      return;
    }
    s.stop();
  });
}

}  // namespace hf::python
