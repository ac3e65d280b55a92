// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core settings as data: the enums (Advection, PressureSolver, SourceEmission,
// ForceFilter), FluidSettings (session::SimulationConfig: grid, fluid, GL device) and
// HapticSessionSettings (session::HapticSessionSettings). Names, units and conversions only: the
// defaults are the engine structs' initialisers, the checks their validate().
#include <pybind11/stl.h>

#include <array>
#include <optional>
#include <string>

#include "fluid/fluid_params.h"
#include "fluid/validate.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/settings_class.h"
#include "session/haptic_session.h"
#include "session/simulation.h"

namespace py = pybind11;

namespace hf::python {
namespace {

using fluid::FluidParams;
using session::HapticSessionSettings;
using session::SimulationConfig;
using Vec3 = std::array<float, 3>;
using IVec3 = std::array<int, 3>;

// Whether the haptic pipeline low-passes the simulation's force (haptics::LowPassSettings::enabled).
enum class ForceFilter { LowPass, None };

py::tuple tuple3(const glm::vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

// A float (the same on every axis) or three floats.
glm::vec3 scaleValue(const py::object& v, const std::string& name) {
  if (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v)) return glm::vec3(v.cast<float>());
  try {
    return toVec3(v.cast<Vec3>());
  } catch (const py::cast_error&) {
    throw InvalidArgument(name + " must be a number or three numbers (x, y, z), got " + py::repr(v).cast<std::string>());
  }
}

void addEnums(py::module_& m) {
  py::enum_<fluid::Advection>(m, "Advection", "How the fields are carried by the flow.")
      .value("semi_lagrangian", fluid::Advection::SemiLagrangian, "first-order backtrace (Stam 1999)")
      .value("maccormack", fluid::Advection::MacCormack, "second-order, limited (Selle et al. 2008)");
  py::enum_<fluid::PressureSolverKind>(m, "PressureSolver", "The pressure solve of each step.")
      .value("jacobi", fluid::PressureSolverKind::Jacobi, "cheap sweeps, slow to converge")
      .value("multigrid", fluid::PressureSolverKind::Multigrid,
             "conjugate gradient preconditioned by a geometric multigrid V-cycle");
  py::enum_<fluid::SourceEmission>(m, "SourceEmission", "How a smoke source changes the cells it covers.")
      .value("hold", fluid::SourceEmission::Hold, "cells held at least at the source's values")
      .value("rate", fluid::SourceEmission::Rate, "the source's values added per second");
  py::enum_<session::Feel>(m, "Feel", "What the hand feels of the fluid's force when the gain is derived.")
      .value("amplified", session::Feel::Amplified,
             "the largest gain the coupled rendering holds passively, with its margin")
      .value("physical", session::Feel::Physical,
             "the fluid's newtons (gain 1) where the rendering holds it, else that largest gain");
  py::enum_<ForceFilter>(m, "ForceFilter", "What the haptic pipeline does to the simulation's force.")
      .value("lowpass", ForceFilter::LowPass, "the seed's first-order low-pass, cutoff from the simulation rate")
      .value("none", ForceFilter::None, "no filter");
}

}  // namespace

// The fluid's settings (FluidParams), listed once: FluidSettings' fields and Simulation's
// properties (which change them between steps) are both made from this table.
const SettingTable<FluidParams>& fluidParamSettings() {
  using P = FluidParams;
  static const SettingTable<P> table = [] {
    SettingTable<P> t;
    t.add<float>("fluid_density", [](const P& p) { return p.density_kg_m3; }, [](P& p, float v) { p.density_kg_m3 = v; },
                 "rho (kg/m^3): 1.2 for air, 1000 for water.", fluid::kFluidDensityRange)
        .add<Vec3>("gravity", [](const P& p) { return tuple3(p.gravity_m_s2); },
                   [](P& p, const Vec3& v) { p.gravity_m_s2 = toVec3(v); },
                   "Acceleration (m/s^2, at most 1000 in magnitude); gives the hydrostatic pressure (buoyancy on\n"
                   "the probe).")
        .add<bool>("open_top", [](const P& p) { return p.open_top; }, [](P& p, bool v) { p.open_top = v; },
                   "The +z wall is open to 0 Pa instead of closed (needs gravity along -z, or none).")
        .add<fluid::Advection>("advection", [](const P& p) { return p.advection; },
                               [](P& p, fluid::Advection v) { p.advection = v; }, "Advection scheme (Advection or its name).")
        .add<float>("vorticity", [](const P& p) { return p.vorticity_confinement; },
                    [](P& p, float v) { p.vorticity_confinement = v; }, "Vorticity confinement epsilon (dimensionless).",
                    fluid::kVorticityRange)
        .add<float>("smoke_weight", [](const P& p) { return p.smoke_weight_m_s2; },
                    [](P& p, float v) { p.smoke_weight_m_s2 = v; },
                    "Downward acceleration per unit smoke concentration (m/s^2).", fluid::kSmokeWeightRange)
        .add<float>("heat_buoyancy", [](const P& p) { return p.heat_buoyancy_m_s2_k; },
                    [](P& p, float v) { p.heat_buoyancy_m_s2_k = v; },
                    "Upward acceleration per kelvin above ambient (m/s^2/K).", fluid::kHeatBuoyancyRange)
        .add<float>("smoke_dissipation", [](const P& p) { return p.density_dissipation_1_s; },
                    [](P& p, float v) { p.density_dissipation_1_s = v; }, "Smoke fade rate (1/s).", fluid::kDissipationRange)
        .add<float>("heat_dissipation", [](const P& p) { return p.temperature_dissipation_1_s; },
                    [](P& p, float v) { p.temperature_dissipation_1_s = v; }, "Heat fade rate (1/s).",
                    fluid::kDissipationRange)
        .add<bool>("conserve_smoke", [](const P& p) { return p.conserve_smoke; }, [](P& p, bool v) { p.conserve_smoke = v; },
                   "Advection keeps the totals of smoke and heat (less the outflow through an open top),\n"
                   "without new extrema; off: the raw transport, which loses some.")
        .add<fluid::PressureSolverKind>("pressure_solver", [](const P& p) { return p.pressure_solver; },
                                        [](P& p, fluid::PressureSolverKind v) { p.pressure_solver = v; },
                                        "Pressure solver (PressureSolver or its name).")
        .add<int>("pressure_iterations", [](const P& p) { return p.pressure_iterations; },
                  [](P& p, int v) { p.pressure_iterations = v; },
                  "Jacobi sweeps or multigrid CG iterations per step; with a pressure_tolerance, the most.",
                  fluid::kPressureIterationsRange)
        .add<float>("pressure_tolerance", [](const P& p) { return p.pressure_tolerance; },
                    [](P& p, float v) { p.pressure_tolerance = v; },
                    "Relative residual (dimensionless) at which the solve stops early; 0 runs exactly\n"
                    "pressure_iterations. 0, or between 1e-7 (and the grid's pressure_tolerance_floor) and 1\n"
                    "(exclusive).",
                    fluid::kPressureToleranceRange)
        .add<bool>("compute_residual", [](const P& p) { return p.compute_residual; },
                   [](P& p, bool v) { p.compute_residual = v; }, "Measure the pressure solve's relative residual each step.")
        .add<bool>("cut_cells", [](const P& p) { return p.cut_cells; }, [](P& p, bool v) { p.cut_cells = v; },
                   "Cut cells for the probe, sphere or mesh (on by default): the open fractions of the faces\n"
                   "around it from its geometry, used in the divergence, pressure solve, projection and force,\n"
                   "so the force changes continuously as it moves. Off: faces are open or covered by the\n"
                   "probe's voxels (whole cells switch in one step).");
    return t;
  }();
  return table;
}

namespace {

void addFluidSettings(py::module_& m) {
  SettingsClass<SimulationConfig> c(m, "FluidSettings", R"doc(
Everything a Simulation is made with: the grid, the fluid and its solver, the backend and device. SI units.
Simulation(settings) takes one; keywords (FluidSettings(resolution=(32, 32, 32)) or
Simulation(settings, vorticity=0.2)) set the settings of the same names. A value of the wrong
type raises TypeError naming the setting, a value the engine refuses InvalidArgumentError; the
grid's settings are checked together when the Simulation is made. limits() gives the range the
engine takes of each numeric setting that has one.
)doc",
                                    [](const SimulationConfig& c) { session::validate(c); });
  c.field<IVec3>("resolution", [](const SimulationConfig& c) { return py::make_tuple(c.resolution.x, c.resolution.y, c.resolution.z); },
                 [](SimulationConfig& c, const IVec3& r) { c.resolution = glm::ivec3(r[0], r[1], r[2]); },
                 "Cells per axis (nx, ny, nz), each >= 8.")
      .field<Vec3>("domain_size", [](const SimulationConfig& c) { return tuple3(c.domain_size_m); },
                   [](SimulationConfig& c, const Vec3& v) { c.domain_size_m = toVec3(v); },
                   "Box edges (m); with the resolution they must give cubic cells.")
      .field<Vec3>("origin", [](const SimulationConfig& c) { return tuple3(c.origin_m); },
                   [](SimulationConfig& c, const Vec3& v) { c.origin_m = toVec3(v); },
                   "World position of the box's minimum corner (m).")
      .field<std::string>("backend", [](const SimulationConfig& c) { return c.backend; },
                          [](SimulationConfig& c, const std::string& b) { c.backend = b; },
                          "Where the step runs: 'auto' (a hardware GPU if one gives an OpenGL 4.5 context, else the "
                          "CPU backend), 'gpu' (OpenGL on `device`, Mesa's llvmpipe included), 'cpu' (the same "
                          "kernels compiled for the CPU, on cpu_threads threads); '' = HAPTICFLUID_BACKEND or auto.")
      .field<int>("cpu_threads", [](const SimulationConfig& c) { return c.cpu_threads; },
                  [](SimulationConfig& c, int n) { c.cpu_threads = n; },
                  "Threads of the CPU backend (0 = HAPTICFLUID_CPU_THREADS, else one per core); the result does "
                  "not depend on it.")
      .field<std::string>("device", [](const SimulationConfig& c) { return c.device; },
                          [](SimulationConfig& c, const std::string& d) { c.device = d; },
                          "GL device: '' (HAPTICFLUID_EGL_DEVICE or auto: a hardware GPU first), 'software' or an EGL device number.")
      .field<int>("thread_niceness", [](const SimulationConfig& c) { return c.thread_niceness; },
                  [](SimulationConfig& c, int n) { c.thread_niceness = n; },
                  "0..19: how much nicer (Linux niceness) the simulation's GL thread and its driver's threads "
                  "run than the caller; 0 shares the cores equally, more lets an interactive thread (Blender's "
                  "drawing on a CPU GL device) go first.")
      .fields(fluidParamSettings(), &SimulationConfig::params)
      .done();
}

void addHapticSessionSettings(py::module_& m) {
  using S = HapticSessionSettings;
  SettingsClass<S> c(m, "HapticSessionSettings", R"doc(
Everything a HapticSession is made with (SI units). HapticSession(simulation, device, settings)
takes one; keywords set the settings of the same names. A value of the wrong type raises
TypeError naming the setting, a value the engine refuses InvalidArgumentError; limits that
depend on the device (max_force, passivity_max_damping) are checked when the session is made.
)doc",
                     [](const S& s) { s.validate(); });
  c.field<py::object>("workspace_scale", [](const S& s) { return tuple3(s.loop.pipeline.map.scale); },
                      [](S& s, const py::object& v) { s.loop.pipeline.map.scale = scaleValue(v, "HapticSessionSettings.workspace_scale"); },
                      "Domain metres per device metre, a number or (x, y, z); negative flips an axis.")
      .field<bool>("fit_workspace", [](const S& s) { return s.fit_workspace; },
                   [](S& s, bool v) { s.fit_workspace = v; },
                   "Fit the device's workspace to the domain: the largest uniform workspace_scale at which it\n"
                   "fits (the scale's signs kept), its middle at the domain's centre unless workspace_offset is given.")
      .field<std::optional<Vec3>>("workspace_offset",
                                  [](const S& s) -> py::object { return s.workspace_offset_m ? py::object(tuple3(*s.workspace_offset_m)) : py::none(); },
                                  [](S& s, const std::optional<Vec3>& v) {
                                    s.workspace_offset_m = v ? std::optional<glm::vec3>(toVec3(*v)) : std::nullopt;
                                  },
                                  "Domain position (m) of the device origin; None: the middle of the device's workspace\n"
                                  "at the domain's centre.")
      .field<std::optional<float>>("force_gain",
                                   [](const S& s) -> py::object { return s.derive_force_gain ? py::none() : py::cast(s.loop.pipeline.map.force_gain); },
                                   [](S& s, const std::optional<float>& g) {
                                     s.derive_force_gain = !g;
                                     if (g) s.loop.pipeline.map.force_gain = *g;
                                   },
                                   "Device newtons per fluid newton (>= 0); None: the gain the device can render (see feel),\n"
                                   "derived by the session: with the coupling, the share of the probe's added mass x workspace\n"
                                   "scale still held per simulation step (at most 10 ms), kept at half the device's max_damping\n"
                                   "and max_stiffness, and the buoyancy at rest at most half of max_force (no cap at 1);\n"
                                   "stats()['force_gain'] and ['force_gain_reason'] say what was chosen.")
      .field<bool>("allow_unsafe_gain", [](const S& s) { return s.allow_unsafe_gain; },
                   [](S& s, bool v) { s.allow_unsafe_gain = v; },
                   "Accept a given force_gain above what the device renders passively (refused otherwise,\n"
                   "naming that limit): the rendering may then put energy into the hand.")
      .field<session::Feel>("feel", [](const S& s) { return s.feel; }, [](S& s, session::Feel f) { s.feel = f; },
                            "With force_gain None: Feel.amplified (the largest gain the rendering holds passively)\n"
                            "or Feel.physical (1:1 where it holds, else that gain; the reason says so). stats()'s\n"
                            "hand_force (device N) against probe_force (fluid N) is what the hand feels of the fluid.")
      .field<bool>("coupling", [](const S& s) { return s.loop.pipeline.coupling.enabled; },
                   [](S& s, bool v) { s.loop.pipeline.coupling.enabled = v; },
                   "Render the force at the haptic rate: each step identifies a local model of the fluid's force\n"
                   "(added mass, drag, steady part) and a proxy carrying it is coupled to the hand by a\n"
                   "spring-damper inside the device's limits. False: the low-passed step force (the seed's).\n"
                   "A device that reports no rendering limits keeps the latter; stats()['coupling'] says which.")
      .field<float>("coupling_stiffness", [](const S& s) { return s.loop.pipeline.coupling.stiffness_n_m; },
                    [](S& s, float v) { s.loop.pipeline.coupling.stiffness_n_m = v; },
                    "The coupling's spring (N/m); 0: a quarter of the device's max_stiffness.")
      .field<float>("coupling_damping", [](const S& s) { return s.loop.pipeline.coupling.damping_n_s_m; },
                    [](S& s, float v) { s.loop.pipeline.coupling.damping_n_s_m = v; },
                    "The coupling's damper (N s/m); 0: half the device's max_damping.")
      .field<float>("guide_stiffness", [](const S& s) { return s.loop.pipeline.guide.stiffness_n_m; },
                    [](S& s, float v) { s.loop.pipeline.guide.stiffness_n_m = v; },
                    "Haptic playback (HapticSession.set_guide): the guide's spring pulling the grip to the played\n"
                    "pose (N/m); 0: a quarter of the device's max_stiffness. With the coupling's, at most the device's.")
      .field<float>("guide_damping", [](const S& s) { return s.loop.pipeline.guide.damping_n_s_m; },
                    [](S& s, float v) { s.loop.pipeline.guide.damping_n_s_m = v; },
                    "The guide's damper on the grip's velocity against the played one (N s/m); 0: a quarter of the\n"
                    "device's max_damping. With the coupling's, at most the device's.")
      .field<float>("guide_max_force", [](const S& s) { return s.loop.pipeline.guide.max_force_n; },
                    [](S& s, float v) { s.loop.pipeline.guide.max_force_n = v; },
                    "The guide's force bound (N), at most max_force; 0: half of max_force (the hand can resist it\n"
                    "and the fluid's force keeps room).")
      .field<double>("guide_ramp", [](const S& s) { return s.loop.pipeline.guide.ramp_s; },
                     [](S& s, double v) { s.loop.pipeline.guide.ramp_s = v; },
                     "The guide fades in and out over this long (s, 0.01 .. 5), and the fluid's probe is handed\n"
                     "over between the grip and the played pose over the same time.")
      .field<double>("guide_stale", [](const S& s) { return s.loop.pipeline.guide.stale_s; },
                     [](S& s, double v) { s.loop.pipeline.guide.stale_s = v; },
                     "A played pose not renewed within this long (s, 0.05 .. 10) is let go; until then it is\n"
                     "carried forward at its velocity.")
      .field<std::optional<float>>("probe_radius", [](const S& s) { return s.probe_radius_m; },
                                   [](S& s, const std::optional<float>& r) { s.probe_radius_m = r; },
                                   "The probe becomes a sphere of this radius (m, >= one cell); None: keep the simulation's\n"
                                   "probe, or a 0.1 m sphere if it has none.")
      .field<ForceFilter>("filter", [](const S& s) { return s.loop.pipeline.filter.enabled ? ForceFilter::LowPass : ForceFilter::None; },
                          [](S& s, ForceFilter f) { s.loop.pipeline.filter.enabled = f == ForceFilter::LowPass; },
                          "Filter on the simulation's force (ForceFilter or its name).")
      .field<double>("bandwidth_ratio", [](const S& s) { return s.loop.pipeline.filter.bandwidth_ratio; },
                     [](S& s, double v) { s.loop.pipeline.filter.bandwidth_ratio = v; },
                     "Low-pass cutoff / measured simulation rate (dimensionless, > 0).")
      .field<double>("max_cutoff_per_rate", [](const S& s) { return s.max_cutoff_per_rate; },
                     [](S& s, double v) { s.max_cutoff_per_rate = v; },
                     "The low-pass cutoff is at most this fraction of the haptic rate ((0, 0.5]).")
      .field<bool>("prediction", [](const S& s) { return s.loop.pipeline.prediction; },
                   [](S& s, bool v) { s.loop.pipeline.prediction = v; },
                   "Update the force between frames with a fitted local drag model F0 + B (v - v0).")
      .field<std::optional<float>>("max_force", [](const S& s) { return s.max_force_n; },
                                   [](S& s, const std::optional<float>& v) { s.max_force_n = v; },
                                   "Bound on the commanded force (N), at most the device's maximum; None: that maximum.")
      .field<float>("slew_rate", [](const S& s) { return s.loop.pipeline.safety.slew_rate_n_s; },
                    [](S& s, float v) { s.loop.pipeline.safety.slew_rate_n_s = v; }, "Largest change of the commanded force (N/s).")
      .field<double>("ramp_time", [](const S& s) { return s.loop.pipeline.safety.ramp_s; },
                     [](S& s, double v) { s.loop.pipeline.safety.ramp_s = v; },
                     "The force ramps in linearly over this long after start, resume and homing (s).")
      .field<double>("stale_after", [](const S& s) { return s.loop.pipeline.safety.stale_after_s; },
                     [](S& s, double v) { s.loop.pipeline.safety.stale_after_s = v; },
                     "A force older than this (s, at least) starts fading.")
      .field<double>("stale_periods", [](const S& s) { return s.loop.pipeline.safety.stale_periods; },
                     [](S& s, double v) { s.loop.pipeline.safety.stale_periods = v; },
                     "... or older than this many measured simulation periods, whichever is longer.")
      .field<double>("stale_after_max", [](const S& s) { return s.loop.pipeline.safety.stale_after_max_s; },
                     [](S& s, double v) { s.loop.pipeline.safety.stale_after_max_s = v; },
                     "... but at most this old (s): a stalled simulation's force still fades.")
      .field<double>("fade_time", [](const S& s) { return s.loop.pipeline.safety.fade_s; },
                     [](S& s, double v) { s.loop.pipeline.safety.fade_s = v; }, "A stale force reaches zero this much later (s).")
      .field<bool>("passivity", [](const S& s) { return s.loop.pipeline.passivity.enabled; },
                   [](S& s, bool v) { s.loop.pipeline.passivity.enabled = v; },
                   "The passivity controller damps energy the loop made (Hannaford and Ryu 2002); False: observe only.")
      .field<std::optional<float>>("passivity_max_damping", [](const S& s) { return s.loop.pipeline.passivity.max_damping_n_s_m; },
                                   [](S& s, const std::optional<float>& d) { s.loop.pipeline.passivity.max_damping_n_s_m = d; },
                                   "Bound on the controller's damping (N s/m, > 0); None: the device's max_damping.")
      .field<float>("passivity_deadband", [](const S& s) { return s.loop.pipeline.passivity.velocity_deadband_m_s; },
                    [](S& s, float v) { s.loop.pipeline.passivity.velocity_deadband_m_s = v; },
                    "Below this device speed (m/s) no damping is applied.")
      .field<double>("passivity_reserve", [](const S& s) { return s.loop.pipeline.passivity.max_reserve_j; },
                     [](S& s, double v) { s.loop.pipeline.passivity.max_reserve_j = v; },
                     "Most stored dissipation (J) the observer keeps.")
      .field<double>("passivity_memory", [](const S& s) { return s.loop.pipeline.passivity.reserve_decay_s; },
                     [](S& s, double v) { s.loop.pipeline.passivity.reserve_decay_s = v; },
                     "Time constant (s) over which stored dissipation is forgotten.")
      .field<double>("rate", [](const S& s) { return s.loop.rate_hz; }, [](S& s, double v) { s.loop.rate_hz = v; },
                     "Haptic loop rate (Hz, 100..10000).")
      .field<double>("sim_dt", [](const S& s) { return s.sim_dt_s; }, [](S& s, double v) { s.sim_dt_s = v; },
                     "Fixed simulation step (s), stepped as fast as the GPU goes; 0: real time.")
      .field<double>("min_sim_dt", [](const S& s) { return s.min_sim_dt_s; }, [](S& s, double v) { s.min_sim_dt_s = v; },
                     "Real time: the shortest step (s); a step that finishes early waits for it.")
      .field<double>("max_sim_dt", [](const S& s) { return s.max_sim_dt_s; }, [](S& s, double v) { s.max_sim_dt_s = v; },
                     "Real time: the longest step (s).")
      .field<bool>("realtime", [](const S& s) { return s.loop.realtime; }, [](S& s, bool v) { s.loop.realtime = v; },
                   "Ask for SCHED_FIFO priority for the haptic thread (stats()['scheduling'] says if refused).")
      .field<bool>("trace", [](const S& s) { return s.trace; }, [](S& s, bool v) { s.trace = v; },
                   "Keep a record per haptic period for trace().")
      .field<double>("trace_seconds", [](const S& s) { return s.trace_s; }, [](S& s, double v) { s.trace_s = v; },
                     "How many seconds of haptic periods the trace keeps.")
      .field<std::optional<double>>("snapshot", [](const S& s) { return s.snapshot_interval_s; },
                                    [](S& s, const std::optional<double>& v) { s.snapshot_interval_s = v; },
                                    "None: no field snapshots; 0: after every step; s > 0: after the first step at least that\n"
                                    "long (wall time) after the last one.")
      .field<bool>("snapshot_temperature", [](const S& s) { return s.snapshot_temperature; },
                   [](S& s, bool v) { s.snapshot_temperature = v; }, "Snapshots carry the temperature too.")
      .done();
}

}  // namespace

void addSettings(py::module_& m) {
  addEnums(m);
  addFluidSettings(m);
  addHapticSessionSettings(m);
}

}  // namespace hf::python
