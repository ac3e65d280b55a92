// SPDX-License-Identifier: GPL-3.0-or-later
// hapticfluid._core.Simulation and StepReport: argument conversion, docstrings, GIL release.
#include <pybind11/stl.h>

#include <string>

#include "common/error.h"
#include "emitter/mesh_source.h"
#include "fluid/grid_checks.h"
#include "fluid/validate.h"
#include "obstacle/probe_checks.h"
#include "python/bindings.h"
#include "python/convert.h"
#include "python/convert_mesh.h"
#include "python/ensure_array.h"
#include "python/named_args.h"
#include "python/settings_class.h"
#include "session/simulation.h"

namespace py = pybind11;

namespace hf::python {
namespace {

using session::Field;
using session::Simulation;
using Vec3 = std::array<float, 3>;
using IVec3 = std::array<int, 3>;

// An enum value's name ('multigrid'), as the Python enum calls it.
template <class E>
std::string enumName(E e) {
  return py::cast(e).attr("name").template cast<std::string>();
}

py::array_t<float> readField(Simulation& sim, Field f) {
  std::vector<float> data;
  {
    py::gil_scoped_release release;
    data = sim.readFloat(f);
  }
  return fieldArray(std::move(data), sim.fieldShape(f));
}

// The fluid's settings as properties: read from the settings in use, written as one change that
// applies if the engine's checks pass (Simulation::updateParams).
void addParamProperties(py::class_<Simulation>& c) {
  for (const Setting<fluid::FluidParams>& row : fluidParamSettings().rows()) {
    c.def_property(
        row.name.c_str(), [get = row.get](const Simulation& s) { return get(s.params()); },
        [set = row.set, qualified = "Simulation." + row.name](Simulation& s, const py::object& value) {
          fluid::FluidParams changed = s.params();
          set(changed, value, qualified);
          s.updateParams([&changed](fluid::FluidParams& p) { p = changed; });
        },
        (row.doc + " As FluidSettings." + row.name + ", changed between steps.").c_str());
  }
}

// The checkpoint's arrays by their Python names, in the dict state() returns.
constexpr const char* kStateArrays[] = {"velocity_x", "velocity_y", "velocity_z", "density", "temperature", "pressure"};

BulkFloats& stateArray(session::SimulationState& s, int i) {
  BulkFloats* arrays[] = {&s.velocity_x, &s.velocity_y, &s.velocity_z, &s.density, &s.temperature,
                                  &s.dynamic_pressure};
  return *arrays[i];
}

Field stateField(int i) {
  const Field fields[] = {Field::VelocityX, Field::VelocityY, Field::VelocityZ,
                          Field::Density, Field::Temperature, Field::DynamicPressure};
  return fields[i];
}

py::dict stateDict(Simulation& sim) {
  session::SimulationState st;
  {
    py::gil_scoped_release release;
    st = sim.saveState();
  }
  py::dict d;
  for (int i = 0; i < 6; ++i) d[kStateArrays[i]] = fieldArray(std::move(stateArray(st, i)), sim.fieldShape(stateField(i)));
  d["time"] = st.time_s;
  d["steps"] = st.steps;
  return d;
}

// dict -> SimulationState: every key present, float32 arrays of the field's shape.
session::SimulationState stateFromDict(const Simulation& sim, const py::dict& d) {
  session::SimulationState st;
  for (int i = 0; i < 6; ++i) {
    const char* key = kStateArrays[i];
    if (!d.contains(key)) throw InvalidArgument(std::string("state is missing '") + key + "'");
    py::array a = ensureArray<py::array>(d[key]);
    if (!a) throw InvalidArgument(std::string("state['") + key + "'] must be a numpy array");
    if (!a.dtype().is(py::dtype::of<float>())) {
      throw InvalidArgument(std::string("state['") + key + "'] must be float32 (as state() returns), got " +
                            std::string(py::str(a.dtype())));
    }
    const glm::ivec3 shape = sim.fieldShape(stateField(i));
    if (a.ndim() != 3 || a.shape(0) != shape.x || a.shape(1) != shape.y || a.shape(2) != shape.z) {
      throw InvalidArgument(std::string("state['") + key + "'] must have shape (" + std::to_string(shape.x) + ", " +
                            std::to_string(shape.y) + ", " + std::to_string(shape.z) + "), got " +
                            std::string(py::str(py::getattr(a, "shape"))));
    }
    // The Fortran-ordered copy (none for what state() returned) may not fit: MemoryError propagates.
    auto f = ensureArray<py::array_t<float, py::array::f_style | py::array::forcecast>>(a);
    if (!f) throw InvalidArgument(std::string("state['") + key + "'] cannot be converted to float32");
    stateArray(st, i).assign(f.data(), f.data() + f.size());
  }
  for (const char* key : {"time", "steps"}) {
    if (!d.contains(key)) throw InvalidArgument(std::string("state is missing '") + key + "'");
  }
  try {
    st.time_s = d["time"].cast<double>();
    st.steps = d["steps"].cast<std::int64_t>();
  } catch (const py::cast_error&) {
    throw InvalidArgument("state['time'] must be a number (s) and state['steps'] an integer");
  }
  return st;
}

// StepReport: what one step measured.
void addStepReport(py::module_& m) {
  py::class_<session::StepReport>(m, "StepReport", "What one step measured.")
      .def_property_readonly("force", [](const session::StepReport& r) { return vec3Array(r.force_n); },
                             "Fluid force on the probe (N), numpy array (3,).")
      .def_property_readonly("torque", [](const session::StepReport& r) { return vec3Array(r.torque_n_m); },
                             "Fluid torque on the probe (N m) about torque_centre, numpy array (3,), from the\n"
                             "same exposed-face pressures as the force.")
      .def_property_readonly("torque_centre",
                             [](const session::StepReport& r) { return vec3Array(r.torque_centre_m); },
                             "World point (m) the torque is taken about, numpy array (3,): the probe's\n"
                             "torque_centre if one was given, else the centroid of the cells it covers.")
      .def_readonly("exposed_faces", &session::StepReport::exposed_faces,
                    "Number of boundary/surrounding faces summed into the force.")
      .def_readonly("solid_cells", &session::StepReport::solid_cells,
                    "Cells the probe covered this step (its voxelized volume is solid_cells * cell_size^3).")
      .def_readonly("pressure_iterations", &session::StepReport::pressure_iterations,
                    "Jacobi sweeps or multigrid CG iterations the pressure solve ran.")
      .def_readonly("relative_residual", &session::StepReport::relative_residual,
                    "||rhs - A p|| / ||rhs|| of the pressure solve (dimensionless); with compute_residual off,\n"
                    "the solver's own estimate in tolerance mode, else -1 (not measured).")
      .def_readonly("initial_relative_residual", &session::StepReport::initial_relative_residual,
                    "||rhs - A p|| / ||rhs|| of the warm start before the pressure solve (dimensionless), measured\n"
                    "in tolerance mode (pressure_tolerance > 0); -1 otherwise.")
      .def_readonly("converged", &session::StepReport::converged,
                    "Tolerance mode: the pressure solve reached pressure_tolerance within pressure_iterations;\n"
                    "always True in fixed-count mode.")
      .def_readonly("warning", &session::StepReport::warning,
                    "Set on the first step of the simulation whose solve did not converge, else ''.")
      .def_readonly("wall_ms", &session::StepReport::wall_ms, "Host time of the step (ms).")
      .def_property_readonly(
          "gpu_ms",
          [](const session::StepReport& r) {
            py::dict d;
            for (const auto& [k, v] : r.gpu_ms) d[py::str(k)] = v;
            return d;
          },
          "GPU time per stage (ms), in execution order.")
      .def("__repr__", [](const session::StepReport& r) {
        return "StepReport(force=(" + std::to_string(r.force_n.x) + ", " + std::to_string(r.force_n.y) + ", " +
               std::to_string(r.force_n.z) + ") N, torque=(" + std::to_string(r.torque_n_m.x) + ", " +
               std::to_string(r.torque_n_m.y) + ", " + std::to_string(r.torque_n_m.z) + ") N m, residual=" + std::to_string(r.relative_residual) +
               ", wall_ms=" + std::to_string(r.wall_ms) + ")";
      });

}

// The probe: a sphere or a closed mesh, its pose, and what the simulation holds.
void addProbeMethods(py::class_<Simulation>& c) {
  defNamed(
      c, "set_probe",
      [](Simulation& s, const Vec3& centre, float radius, const Vec3& velocity, const Vec3& angular_velocity) {
        obstacle::SpherePose pose;
        pose.centre_m = toVec3(centre);
        pose.radius_m = radius;
        pose.velocity_m_s = toVec3(velocity);
        pose.angular_velocity_rad_s = toVec3(angular_velocity);
        s.setSphereProbe(pose);
      },
      py::arg("centre"), py::arg("radius"), py::arg("velocity") = Vec3{0, 0, 0},
      py::arg("angular_velocity") = Vec3{0, 0, 0},
      "Place the spherical probe: centre (m, world), radius (m, >= one cell), linear velocity (m/s)\n"
      "and angular velocity (rad/s) imposed on the fluid faces it covers. It must lie inside the domain.");
  defNamed(
      c, "set_mesh_probe",
      [](Simulation& s, const py::array& vertices, const py::array& triangles, const py::object& transform,
         const Vec3& velocity, const Vec3& angular_velocity, const std::optional<Vec3>& torque_centre) {
        obstacle::TriangleMesh mesh = toMesh(vertices, triangles);
        obstacle::RigidPose pose;
        pose.transform = toTransform(transform);
        pose.velocity_m_s = toVec3(velocity);
        pose.angular_velocity_rad_s = toVec3(angular_velocity);
        std::optional<glm::vec3> centre;
        if (torque_centre) centre = toVec3(*torque_centre);
        py::gil_scoped_release release;
        s.setMeshProbe(std::move(mesh), pose, centre);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("transform") = py::none(),
      py::arg("velocity") = Vec3{0, 0, 0}, py::arg("angular_velocity") = Vec3{0, 0, 0},
      py::arg("torque_centre") = py::none(), R"doc(
Make the probe a rigid closed triangle mesh (replaces any probe). The arrays are copied.

vertices: (N, 3) real numbers, the object's local frame (m).
triangles: (M, 3) integers, vertex indices, counter-clockwise seen from outside (a mesh that is
    inside out as a whole works too).
transform: 4x4 local -> world matrix (the object's matrix_world; rows, translation in the last
    column, m; may rotate, scale and mirror), or None for the identity.
velocity: velocity of the object's origin (the transform's translation), m/s.
angular_velocity: rad/s, world frame, about the origin; faces the solid covers move at
    velocity + angular_velocity x (x - origin).
torque_centre: world point (m) for StepReport.torque, or None for the centroid of the cells
    the mesh covers. A given point is fixed in the world: set_probe_pose does not move it.

The mesh must be closed and consistently oriented: after merging vertices at identical
positions, every edge is used once in each direction (several shells are fine; zero-area
triangles are fine). A cell is solid when the mesh winds around its centre (nonzero winding
number, counted as signed crossings along z). Parts thinner than a cell can be missed. The
posed mesh's bounding box (a conservative one, from the local box and bounding sphere) must
keep one cell of fluid from every wall. Raises InvalidArgumentError otherwise, saying what to
change; nothing changes then.
)doc");
  defNamed(
      c, "set_probe_pose",
      [](Simulation& s, const py::object& transform, const Vec3& velocity, const Vec3& angular_velocity) {
        obstacle::RigidPose pose;
        pose.transform = toTransform(transform);
        pose.velocity_m_s = toVec3(velocity);
        pose.angular_velocity_rad_s = toVec3(angular_velocity);
        s.setProbePose(pose);
      },
      py::arg("transform"), py::arg("velocity") = Vec3{0, 0, 0}, py::arg("angular_velocity") = Vec3{0, 0, 0},
      R"doc(
Move the current probe without re-uploading its shape: cheap, never waits for the GPU (for a
1 kHz haptic loop or a bake driver); the next step uses the new pose.

transform: 4x4 local -> world matrix (matrix_world, m), or None for the identity. For a sphere
    probe only its translation is used, as the centre.
velocity: of the origin (m/s). angular_velocity: world frame (rad/s).
A mesh's torque_centre, if one was given, stays the same world point; to take the torque
about a point that moves with the body, compute it from the report's torque_centre, force and
torque (tau_c = tau - (c - torque_centre) x force), or call set_mesh_probe again.
Raises InvalidArgumentError if there is no probe or the pose leaves the domain's margin.
)doc");
  c.def("clear_probe", &Simulation::clearProbe, "Remove the probe from the fluid.");
  c.def_property_readonly(
      "probe",
      [](const Simulation& s) -> py::object {
        auto p = s.probe();
        if (!p) return py::none();
        py::dict d;
        if (p->kind == session::ProbeState::Kind::Sphere) {
          d["kind"] = "sphere";
          d["centre"] = vec3Array(p->sphere.centre_m);
          d["radius"] = p->sphere.radius_m;
          d["velocity"] = vec3Array(p->sphere.velocity_m_s);
          d["angular_velocity"] = vec3Array(p->sphere.angular_velocity_rad_s);
        } else {
          d["kind"] = "mesh";
          d["transform"] = transformArray(p->pose.transform);
          d["vertex_count"] = p->mesh->vertices_m.size();
          d["triangle_count"] = p->mesh->triangles.size();
          d["velocity"] = vec3Array(p->pose.velocity_m_s);
          d["angular_velocity"] = vec3Array(p->pose.angular_velocity_rad_s);
        }
        d["torque_centre"] = p->torque_centre_m ? py::object(vec3Array(*p->torque_centre_m)) : py::none();
        return std::move(d);
      },
      "The probe as a dict, or None. Sphere: kind 'sphere', centre (m), radius (m), velocity (m/s),\n"
      "angular_velocity (rad/s). Mesh: kind 'mesh', transform (4x4, m), vertex_count, triangle_count,\n"
      "velocity (m/s), angular_velocity (rad/s). Both: torque_centre (m, or None = centroid).");
}

// The smoke source: a sphere or a closed mesh, its pose, and what the simulation holds.
void addSourceMethods(py::class_<Simulation>& c) {
  defNamed(
      c, "set_smoke_source",
      [](Simulation& s, const Vec3& centre, float radius, float density, float temperature,
         const py::object& emission) {
        fluid::SmokeSource src;
        src.enabled = true;
        src.centre_m = toVec3(centre);
        src.radius_m = radius;
        src.density = density;
        src.temperature_k = temperature;
        src.emission = settingArg<fluid::SourceEmission>(emission, "emission");
        s.setSmokeSource(src);
      },
      py::arg("centre"), py::arg("radius"), py::arg("density") = 1.0f, py::arg("temperature") = 0.0f,
      py::arg("emission") = "hold",
      "Emit smoke in a sphere (replaces any source): centre (m), radius (m). emission 'hold': its cells\n"
      "are held at least at `density` (concentration) and `temperature` (K above ambient); 'rate':\n"
      "`density` (concentration per second) and `temperature` (K/s) are added per second.");
  defNamed(
      c, "set_smoke_source_mesh",
      [](Simulation& s, const py::array& vertices, const py::array& triangles, const py::object& transform,
         float density, float temperature, const py::object& emission) {
        obstacle::TriangleMesh mesh = toMesh(vertices, triangles);
        const glm::mat4 m = toTransform(transform);
        const fluid::SourceEmission e = settingArg<fluid::SourceEmission>(emission, "emission");
        py::gil_scoped_release release;
        s.setMeshSmokeSource(std::move(mesh), m, density, temperature, e);
      },
      py::arg("vertices"), py::arg("triangles"), py::arg("transform") = py::none(), py::arg("density") = 1.0f,
      py::arg("temperature") = 0.0f, py::arg("emission") = "hold", R"doc(
Make the smoke source a closed triangle mesh emitting from its volume (replaces any source;
Mantaflow's mesh flow object). The arrays are copied.

vertices: (N, 3) real numbers, the object's local frame (m).
triangles: (M, 3) integers, vertex indices; the mesh must be closed and consistently oriented,
    as for set_mesh_probe (several shells are fine; overlapping shells count their overlap twice
    in partly covered cells).
transform: 4x4 local -> world matrix (matrix_world: rows, translation in the last column, m;
    may rotate, scale and mirror), or None for the identity. set_smoke_source_pose moves it.
density: emission 'hold': smoke concentration (dimensionless) the covered cells are raised to at
    least; 'rate': concentration added per second.
temperature: 'hold': K above ambient; 'rate': K per second.
emission: 'hold' or 'rate'. A cell covered by the fraction c (0..1) gets c times the values:
    each step computes c on the GPU, sampled on SOURCE_SUBSAMPLES^2 vertical lines per cell and
    exact along them, so a moving source emits smoothly rather than cell by cell; a 'rate'
    source of volume V adds density x V x dt of smoke (concentration x m^3) per step.

The posed mesh must meet the domain (the part outside emits nothing) and reach no further than
one domain size past any wall. Cells inside the probe get nothing. Raises InvalidArgumentError
otherwise, saying what to change; nothing changes then.
)doc");
  c.def(
      "set_smoke_source_pose",
      [](Simulation& s, const py::object& transform) { s.setSmokeSourcePose(toTransform(transform)); },
      py::arg("transform"), R"doc(
Move the mesh smoke source without re-uploading it: cheap, never waits for the GPU; the next
step emits at the new pose (call it every step or frame to animate the source).

transform: 4x4 local -> world matrix (matrix_world, m), or None for the identity.
Raises InvalidArgumentError if there is no mesh source or the pose is refused.
)doc");
  c.def_property_readonly(
      "smoke_source",
      [](const Simulation& s) -> py::object {
        py::dict d;
        if (auto m = s.meshSmokeSource()) {
          d["kind"] = "mesh";
          d["transform"] = transformArray(m->transform);
          d["vertex_count"] = m->mesh->vertices_m.size();
          d["triangle_count"] = m->mesh->triangles.size();
          d["density"] = m->density;
          d["temperature"] = m->temperature_k;
          d["emission"] = enumName(m->emission);
          return std::move(d);
        }
        const fluid::SmokeSource src = s.smokeSource();
        if (!src.enabled) return py::none();
        d["kind"] = "sphere";
        d["centre"] = vec3Array(src.centre_m);
        d["radius"] = src.radius_m;
        d["density"] = src.density;
        d["temperature"] = src.temperature_k;
        d["emission"] = enumName(src.emission);
        return std::move(d);
      },
      "The smoke source as a dict, or None. Sphere: kind 'sphere', centre (m), radius (m). Mesh: kind\n"
      "'mesh', transform (4x4, m), vertex_count, triangle_count. Both: density, temperature, emission\n"
      "('hold': concentration and K above ambient; 'rate': per second).");
  c.def("clear_smoke_source", [](Simulation& s) { s.setSmokeSource(fluid::SmokeSource{}); },
        "Stop emitting smoke (removes a sphere or mesh source).");
}

// Stepping and the object's lifetime.
void addStepMethods(py::class_<Simulation>& c) {
  defNamed(
      c, "step",
      [](Simulation& s, double dt) {
        FlushLogAfter flush;  // the simulation's once-only warning, on logger "hapticfluid.fluid"
        py::gil_scoped_release release;
        return s.step(dt);
      },
      py::arg("dt"),
      "Advance by dt seconds (> 0): voxelize the probe, advect, forces, pressure solve, projection,\n"
      "force reduction. Returns a StepReport; blocks until its force is read back. The first step whose\n"
      "pressure solve misses pressure_tolerance logs a warning on logger 'hapticfluid.fluid' (once per simulation).");
  c.def_property_readonly("last_report", &Simulation::lastReport, "The StepReport of the latest step.");
  c.def("reset", &Simulation::reset, py::call_guard<py::gil_scoped_release>(),
        "Fluid at rest, no smoke, time 0; probe and settings kept.");
  c.def("close", &Simulation::close, py::call_guard<py::gil_scoped_release>(),
        "Free the GPU fields and end the GL thread now (also done when the object is collected).\n"
        "Later calls that need the GPU raise HapticFluidError.");
  c.def_property_readonly("closed", &Simulation::closed, "True after close().");
  c.def("__enter__", [](Simulation& s) -> Simulation& { return s; }, py::return_value_policy::reference);
  c.def("__exit__", [](Simulation& s, py::args) {
    py::gil_scoped_release release;
    s.close();
  });
}

// The fields read back, and the checkpoint.
void addFieldMethods(py::class_<Simulation>& c) {
  c.def("density", [](Simulation& s) { return readField(s, Field::Density); },
        "Smoke concentration, float32 (nx, ny, nz).");
  c.def("temperature", [](Simulation& s) { return readField(s, Field::Temperature); },
        "Temperature above ambient (K), float32 (nx, ny, nz).");
  defNamed(
      c, "pressure",
      [](Simulation& s, bool hydrostatic) {
        return readField(s, hydrostatic ? Field::Pressure : Field::DynamicPressure);
      },
      py::arg("hydrostatic") = true,
      "Pressure at cell centres (Pa), float32 (nx, ny, nz). With hydrostatic=True it is the\n"
      "physical pressure (solved dynamic part + rho g.(x - top of the domain)); solid cells hold 0.\n"
      "In a closed box the dynamic part is defined up to a constant.");
  c.def(
      "velocity",
      [](Simulation& s) {
        return py::make_tuple(readField(s, Field::VelocityX), readField(s, Field::VelocityY),
                              readField(s, Field::VelocityZ));
      },
      "Staggered face velocities (m/s): u (nx+1, ny, nz), v (nx, ny+1, nz), w (nx, ny, nz+1).");
  c.def(
      "cell_classes",
      [](Simulation& s) {
        std::vector<std::uint8_t> data;
        {
          py::gil_scoped_release release;
          data = s.readCellClasses();
        }
        return fieldArray(std::move(data), s.grid().res);
      },
      "Cell classes of the latest step, uint8 (nx, ny, nz): 0 outside, 1 surrounding, 2 boundary, 3 inside.");
  c.def("state", &stateDict,
        "Checkpoint: a dict of float32 arrays 'velocity_x' (nx+1, ny, nz), 'velocity_y', 'velocity_z'\n"
        "(m/s on faces), 'density', 'temperature' (K), 'pressure' (dynamic pressure, Pa: the next\n"
        "solve's warm start) and the scalars 'time' (s) and 'steps'. Probe, source and settings are\n"
        "not included. Restoring it with set_state() makes later steps bit-identical.");
  defNamed(
      c, "set_state",
      [](Simulation& s, const py::dict& d) {
        session::SimulationState st = stateFromDict(s, d);
        py::gil_scoped_release release;
        s.restoreState(st);
      },
      py::arg("state"),
      "Restore a dict made by state() (same resolution). Every array must be float32 with its\n"
      "field's shape and finite; checked before anything changes (InvalidArgumentError).");
}

// Module functions and constants of the simulation.
void addConstants(py::module_& m) {
  defNamed(
      m, "estimate_bytes", [](const IVec3& r) { return Simulation::estimateBytes(glm::ivec3(r[0], r[1], r[2])); },
      py::arg("resolution"), "GPU memory (bytes) the fields of a grid of this resolution take.");
  m.attr("STEP_READBACK_BYTES") = Simulation::stepReadbackBytes();  // what step() reads off the GPU
  m.attr("MIN_TIME_STEP_S") = static_cast<double>(fluid::kMinTimeStep);  // step(dt) range, s
  m.attr("MAX_TIME_STEP_S") = static_cast<double>(fluid::kMaxTimeStep);
  // Smoke sources: emission modes, value limits, mesh coverage sampling (vertical lines per cell
  // along x and along y).
  m.attr("SOURCE_EMISSIONS") = py::tuple(m.attr("SourceEmission").attr("__members__"));  // the names
  m.attr("MAX_SOURCE_DENSITY") = static_cast<double>(fluid::kMaxFactor);
  m.attr("MAX_SOURCE_TEMPERATURE_K") = static_cast<double>(fluid::kMaxTemperature);
  m.attr("SOURCE_SUBSAMPLES") = emitter::kSourceSubsamples;
  m.attr("CELL_OUTSIDE") = 0;
  m.attr("CELL_SURROUNDING") = 1;
  m.attr("CELL_BOUNDARY") = 2;
  m.attr("CELL_INSIDE") = 3;
}

// The engine's checks of a probe's place in a grid, without a simulation (no GL): what
// set_probe, set_mesh_probe and set_probe_pose would refuse, for a bake to check its keys first.
void addProbeChecks(py::module_& m) {
  defNamed(
      m, "check_sphere_probe",
      [](const session::SimulationConfig& settings, const Vec3& centre, float radius) {
        obstacle::SpherePose pose;
        pose.centre_m = toVec3(centre);
        pose.radius_m = radius;
        obstacle::validatePose(pose, fluid::makeGrid(settings.resolution, settings.domain_size_m, settings.origin_m));
      },
      py::arg("settings"), py::arg("centre"), py::arg("radius"),
      "Raise InvalidArgumentError as Simulation.set_probe would for a sphere of `radius` (m) at `centre`\n"
      "(m) in the grid of `settings` (a FluidSettings): a radius under one cell, or less than one cell of\n"
      "fluid between the sphere and a wall. Makes no simulation.");
  defNamed(
      m, "check_mesh_probe",
      [](const session::SimulationConfig& settings, const py::array& vertices, const py::array& triangles,
         const py::object& transform) {
        const obstacle::MeshExtent extent = obstacle::meshExtent(toMesh(vertices, triangles));
        obstacle::RigidPose pose;
        pose.transform = toTransform(transform);
        obstacle::validatePose(extent, pose,
                               fluid::makeGrid(settings.resolution, settings.domain_size_m, settings.origin_m));
      },
      py::arg("settings"), py::arg("vertices"), py::arg("triangles"), py::arg("transform") = py::none(),
      "Raise InvalidArgumentError as Simulation.set_mesh_probe would for the pose: the mesh's conservative\n"
      "world box at `transform` (4x4 local -> world, m; None: the identity) keeping less than one cell of\n"
      "fluid from a wall of the grid of `settings` (a FluidSettings), or a transform it cannot use. The\n"
      "arrays as set_mesh_probe takes them; whether the mesh is closed is not checked. Makes no simulation.");
}

}  // namespace

void addSimulation(py::module_& m) {
  addStepReport(m);
  py::class_<Simulation> c(m, "Simulation", R"doc(
A 3D smoke/fluid simulation on the GPU (OpenGL compute, Mesa llvmpipe included) or on the CPU
backend (the same kernels compiled for the CPU), with a rigid probe: a sphere or a closed
triangle mesh, moving with a linear and an angular velocity.

All quantities are SI: metres, seconds, kilograms, newtons, pascals. The grid has cubic cells
(domain_size / resolution must be equal on every axis), z is up. Arrays come back indexed
[i, j, k] (x, y, z).
)doc");
  c.def(py::init([](const py::object& settings, const py::kwargs& kwargs) {
          const session::SimulationConfig cfg = settingsWithKeywords<session::SimulationConfig>(settings, kwargs, "Simulation");
          FlushLogAfter flush;  // the GL context's note (software renderer)
          py::gil_scoped_release release;
          return std::make_unique<Simulation>(cfg);
        }),
        py::arg("settings") = py::none(), R"doc(
settings: a FluidSettings (the grid, the fluid, the GL device), or None for the engine's
    defaults. Keywords set the FluidSettings of the same names on a copy of it:
    Simulation(resolution=(32, 32, 32), fluid_density=1000.0). FluidSettings documents each.
Raises InvalidArgumentError naming the setting the engine cannot use (cells that are not cubic,
a resolution below 8, ...) and HapticFluidError (GlError) when no GL context can be made.
)doc");
  c.def_property_readonly(
      "settings",
      [](const Simulation& s) {
        session::SimulationConfig cfg;
        cfg.resolution = s.grid().res;
        cfg.domain_size_m = s.grid().sizeM();
        cfg.origin_m = s.grid().origin_m;
        cfg.params = s.params();
        cfg.backend = compute::backendName(s.deviceInfo().backend);
        cfg.cpu_threads = s.deviceInfo().threads;
        cfg.device = s.deviceInfo().device_index >= 0 ? std::to_string(s.deviceInfo().device_index) : std::string();
        cfg.thread_niceness = s.threadNiceness();
        return cfg;
      },
      "The FluidSettings in use now (a copy; the backend and, on the GPU, the EGL device number in use).");

  c.def_property_readonly("device", [](const Simulation& s) { return deviceDict(s.deviceInfo()); },
                          "The device in use: backend ('gpu' or 'cpu'), renderer, threads (CPU), vendor, version,\n"
                          "platform, software (a GL renderer on the CPU), memory_bytes, ...");
  c.def_property_readonly("resolution", [](const Simulation& s) {
    const auto r = s.grid().res;
    return py::make_tuple(r.x, r.y, r.z);
  }, "Cells per axis (nx, ny, nz).");
  c.def_property_readonly("cell_size", [](const Simulation& s) { return s.grid().cell_size_m; }, "Cell edge (m).");
  c.def_property_readonly(
      "pressure_tolerance_floor", [](const Simulation& s) { return fluid::pressureToleranceFloor(s.grid()); },
      "The smallest pressure_tolerance this grid accepts (dimensionless): float32 pressure cannot reach less.");
  c.def_property_readonly("domain_size", [](const Simulation& s) { return vec3Array(s.grid().sizeM()); },
                          "Box edges (m).");
  c.def_property_readonly("origin", [](const Simulation& s) { return vec3Array(s.grid().origin_m); },
                          "World position of the box's minimum corner (m).");
  c.def_property_readonly("time", &Simulation::timeS, "Simulated time since the start or reset (s).");
  c.def_property_readonly("steps", &Simulation::steps, "Steps taken since the start or reset.");

  addParamProperties(c);
  addProbeMethods(c);
  addSourceMethods(c);
  addStepMethods(c);
  addFieldMethods(c);
  addConstants(m);
  addProbeChecks(m);
}

}  // namespace hf::python
