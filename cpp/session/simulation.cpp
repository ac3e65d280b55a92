// SPDX-License-Identifier: GPL-3.0-or-later
#include "session/simulation.h"

#include <chrono>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/log_sink.h"
#include "common/finite.h"
#include "compute/compute_worker.h"
#include "common/format.h"
#include "common/thread_priority.h"
#include "fluid/grid_checks.h"
#include "fluid/hydrostatic.h"
#include "fluid/validate.h"
#include "obstacle/cell_class.h"
#include "obstacle/probe_checks.h"
#include "cpu/cpu_device.h"
#include "session/backend_choice.h"
#include "session/step_pipeline.h"

namespace hf::session {

std::size_t Simulation::stepReadbackBytes() { return StepPipeline::kResultSlots * sizeof(glm::vec4); }

void validate(const SimulationConfig& config) {
  fluid::validate(config.params);
  if (config.thread_niceness < 0 || config.thread_niceness > kMaxNicenessIncrement) {
    throw InvalidArgument("thread_niceness must be 0 to " + std::to_string(kMaxNicenessIncrement) +
                          " (how much nicer the simulation's threads run), got " +
                          std::to_string(config.thread_niceness));
  }
  parseBackend(config.backend);
  cpu::resolveThreads(config.cpu_threads);
}

Simulation::Simulation(const SimulationConfig& config)
    : grid_(fluid::makeGrid(config.resolution, config.domain_size_m, config.origin_m)), params_(config.params) {
  validate(config);
  fluid::checkPressureTolerance(params_, grid_);
  worker_ = startWorker(config.backend, config.device, config.cpu_threads, config.thread_niceness);
  thread_niceness_ = config.thread_niceness;
  info_ = worker_->info();
  fluid::checkFits(grid_, info_);
  pipeline_ = worker_->call([this] { return std::make_unique<StepPipeline>(grid_); });
  last_rho_g_ = params_.density_kg_m3 * params_.gravity_m_s2;
  last_reference_m_ = fluid::hydrostaticReference(grid_, params_.gravity_m_s2);
}

Simulation::~Simulation() { close(); }

template <class F>
auto Simulation::onGl(F&& fn) {
  std::lock_guard<std::mutex> lock(gpu_mutex_);
  if (!pipeline_) throw Error("this simulation was closed; make a new one");
  return worker_->call([&] { return fn(*pipeline_); });
}

void Simulation::close() {
  std::lock_guard<std::mutex> lock(gpu_mutex_);
  if (worker_ && pipeline_) {
    try {
      worker_->call([this] { pipeline_.reset(); });
    } catch (...) {
      // Closing must not throw. Device objects may only die on the device's thread, so if that failed
      // they are abandoned here and freed with the context when the worker ends.
      static_cast<void>(pipeline_.release());
    }
  }
  worker_.reset();
  closed_ = true;
}

fluid::FluidParams Simulation::params() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return params_;
}

void Simulation::setParams(const fluid::FluidParams& params) {
  fluid::validate(params);
  fluid::checkPressureTolerance(params, grid_);
  std::lock_guard<std::mutex> lock(state_mutex_);
  params_ = params;
}

void Simulation::setSmokeSource(const fluid::SmokeSource& source) {
  fluid::validate(source, grid_);
  std::lock_guard<std::mutex> lock(state_mutex_);
  source_ = source;
  mesh_source_.reset();
}

void Simulation::setMeshSmokeSource(obstacle::TriangleMesh mesh, const glm::mat4& transform, float density,
                                    float temperature_k, fluid::SourceEmission emission) {
  emitter::MeshSource s = emitter::makeMeshSource(std::move(mesh), transform, density, temperature_k, emission, grid_);
  std::lock_guard<std::mutex> lock(state_mutex_);
  source_ = fluid::SmokeSource{};
  mesh_source_ = std::move(s);
}

void Simulation::setSmokeSourcePose(const glm::mat4& transform) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!mesh_source_) {
    throw InvalidArgument("there is no mesh smoke source to move; call set_smoke_source_mesh first");
  }
  emitter::validateSourcePose(mesh_source_->extent, transform, grid_);
  mesh_source_->transform = transform;
}

std::optional<emitter::MeshSource> Simulation::meshSmokeSource() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return mesh_source_;
}

void Simulation::updateParams(const std::function<void(fluid::FluidParams&)>& edit) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  fluid::FluidParams p = params_;
  edit(p);
  fluid::validate(p);
  fluid::checkPressureTolerance(p, grid_);
  params_ = p;
}

fluid::SmokeSource Simulation::smokeSource() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return source_;
}

void Simulation::setSphereProbe(const obstacle::SpherePose& pose) {
  obstacle::validatePose(pose, grid_);
  ProbeState state;
  state.kind = ProbeState::Kind::Sphere;
  state.sphere = pose;
  std::lock_guard<std::mutex> lock(state_mutex_);
  probe_ = std::move(state);
}

void Simulation::setMeshProbe(obstacle::TriangleMesh mesh, const obstacle::RigidPose& pose,
                              const std::optional<glm::vec3>& torque_centre_m) {
  obstacle::validateMesh(mesh);
  if (torque_centre_m && !allFinite(*torque_centre_m)) {
    throw InvalidArgument("torque centre must be a finite world point (m), got " + vecText(*torque_centre_m));
  }
  ProbeState state;
  state.kind = ProbeState::Kind::Mesh;
  state.extent = obstacle::meshExtent(mesh);
  obstacle::validatePose(state.extent, pose, grid_);
  state.mesh = std::make_shared<const obstacle::TriangleMesh>(std::move(mesh));
  state.pose = pose;
  state.torque_centre_m = torque_centre_m;
  std::lock_guard<std::mutex> lock(state_mutex_);
  probe_ = std::move(state);
}

void Simulation::setProbePose(const obstacle::RigidPose& pose) {
  // O(1) checks, done under the short state lock so the pose applies to the probe it was checked for.
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!probe_) throw InvalidArgument("there is no probe to move; call set_probe or set_mesh_probe first");
  if (probe_->kind == ProbeState::Kind::Sphere) {
    obstacle::validateTransform(pose.transform);
    obstacle::SpherePose sphere = probe_->sphere;
    sphere.centre_m = pose.originM();
    sphere.velocity_m_s = pose.velocity_m_s;
    sphere.angular_velocity_rad_s = pose.angular_velocity_rad_s;
    obstacle::validatePose(sphere, grid_);
    probe_->sphere = sphere;
  } else {
    obstacle::validatePose(probe_->extent, pose, grid_);
    probe_->pose = pose;
  }
}

void Simulation::clearProbe() {
  std::lock_guard<std::mutex> lock(state_mutex_);
  probe_.reset();
}

std::optional<obstacle::SpherePose> Simulation::sphereProbe() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!probe_ || probe_->kind != ProbeState::Kind::Sphere) return std::nullopt;
  return probe_->sphere;
}

std::optional<ProbeState> Simulation::probe() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return probe_;
}

StepReport Simulation::step(double dt_in_s) {
  StepInputs in;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    in.params = params_;
    in.source = source_;
    in.mesh_source = mesh_source_;
    in.probe = probe_;
  }
  fluid::validateStep(dt_in_s, in.params, grid_);
  in.dt_s = static_cast<float>(dt_in_s);
  in.rho_g = in.params.density_kg_m3 * in.params.gravity_m_s2;
  in.reference_m = fluid::hydrostaticReference(grid_, in.params.gravity_m_s2);
  const auto t0 = std::chrono::steady_clock::now();
  StepReport r = onGl([&](StepPipeline& pipeline) {
    StepReport out = pipeline.step(in);
    // Under the GPU lock with the fields it describes: a saveState() sees both or neither.
    std::lock_guard<std::mutex> lock(state_mutex_);
    time_s_ += in.dt_s;
    ++steps_;
    return out;
  });
  r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::lock_guard<std::mutex> lock(state_mutex_);
  if (!r.converged && !warned_unconverged_) {
    warned_unconverged_ = true;
    r.warning = "raise pressure_iterations (or pressure_tolerance): the pressure solve stopped at " +
                std::to_string(r.pressure_iterations) + " iterations with relative residual " +
                num(r.relative_residual) + ", above the tolerance " + num(in.params.pressure_tolerance) +
                " (said once per simulation; StepReport.converged tells every step)";
    log::warning("hapticfluid.fluid", r.warning);  // any thread (a HapticSession's too): queued
  }
  last_ = r;
  last_rho_g_ = in.rho_g;
  last_reference_m_ = in.reference_m;
  return r;
}

StepReport Simulation::lastReport() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return last_;
}

double Simulation::timeS() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return time_s_;
}

std::int64_t Simulation::steps() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return steps_;
}

void Simulation::reset() {
  onGl([](StepPipeline& pipeline) { pipeline.reset(); });
  std::lock_guard<std::mutex> lock(state_mutex_);
  time_s_ = 0.0;
  steps_ = 0;
  last_ = StepReport{};
}

namespace {

const char* fieldName(Field f) {
  switch (f) {
    case Field::Density: return "density";
    case Field::Temperature: return "temperature";
    case Field::Pressure: return "pressure";
    case Field::DynamicPressure: return "dynamic pressure";
    case Field::VelocityX: return "velocity x";
    case Field::VelocityY: return "velocity y";
    case Field::VelocityZ: return "velocity z";
    case Field::CellClass: return "cell classes";
  }
  return "field";
}

// The texture holding field f now (Pressure and DynamicPressure: the solved pressure, to which
// readFloat adds the hydrostatic part); cell classes are bytes, not here.
compute::Texture3D& fieldTexture(fluid::FluidFields& fl, Field f) {
  switch (f) {
    case Field::Density: return fl.density.cur();
    case Field::Temperature: return fl.temperature.cur();
    case Field::Pressure:
    case Field::DynamicPressure: return fl.pressure.cur();
    case Field::VelocityX: return fl.vel[0].cur();
    case Field::VelocityY: return fl.vel[1].cur();
    case Field::VelocityZ: return fl.vel[2].cur();
    case Field::CellClass: break;
  }
  throw InvalidArgument(std::string(fieldName(f)) + " is not a float field");
}

void checkWritable(Field f, const float* data, std::size_t count, const glm::ivec3& shape) {
  if (f == Field::Pressure || f == Field::CellClass) {
    throw InvalidArgument(std::string(fieldName(f)) +
                          " cannot be written: write the dynamic pressure (the hydrostatic part is analytic); "
                          "cell classes are recomputed every step");
  }
  const std::size_t n = static_cast<std::size_t>(shape.x) * shape.y * shape.z;
  if (count != n) {
    throw InvalidArgument(std::string(fieldName(f)) + " needs " + std::to_string(n) + " values (shape " +
                          ivecText(shape) + "), got " + std::to_string(count));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(data[i])) {
      throw InvalidArgument(std::string(fieldName(f)) + " holds a non-finite value at flat index " +
                            std::to_string(i));
    }
  }
}

}  // namespace

glm::ivec3 Simulation::fieldShape(Field f) const {
  if (f == Field::VelocityX) return grid_.faceSize(0);
  if (f == Field::VelocityY) return grid_.faceSize(1);
  if (f == Field::VelocityZ) return grid_.faceSize(2);
  return grid_.res;
}

std::vector<float> Simulation::readFloat(Field f) {
  if (f == Field::CellClass) throw InvalidArgument("cell classes are bytes: use readCellClasses()");
  const glm::ivec3 shape = fieldShape(f);
  std::vector<float> out(static_cast<std::size_t>(shape.x) * shape.y * shape.z);
  std::vector<std::uint8_t> classes;
  if (f == Field::Pressure) classes.resize(out.size());
  onGl([&](StepPipeline& e) {
    auto& fl = e.fields();
    fieldTexture(fl, f).download(out.data(), out.size() * sizeof(float));
    if (!classes.empty()) fl.cell_class.download(classes.data(), classes.size());
  });
  if (f == Field::Pressure) {
    // Physical pressure = solved dynamic part + the last step's rho g . (x - reference); solids 0.
    glm::vec3 rho_g, ref;
    {
      std::lock_guard<std::mutex> lock(state_mutex_);
      rho_g = last_rho_g_;
      ref = last_reference_m_;
    }
    std::size_t n = 0;
    for (int k = 0; k < shape.z; ++k) {
      for (int j = 0; j < shape.y; ++j) {
        for (int i = 0; i < shape.x; ++i, ++n) {
          if (classes[n] >= static_cast<std::uint8_t>(obstacle::CellClass::Boundary)) continue;
          const glm::vec3 x = grid_.toWorld(glm::vec3(i, j, k) + 0.5f);
          out[n] += glm::dot(rho_g, x - ref);
        }
      }
    }
  }
  return out;
}

std::vector<std::uint8_t> Simulation::readCellClasses() {
  std::vector<std::uint8_t> out(grid_.cells());
  onGl([&](StepPipeline& e) { e.fields().cell_class.download(out.data(), out.size()); });
  return out;
}

std::size_t Simulation::estimateBytes(const glm::ivec3& resolution) {
  fluid::checkResolution(resolution);
  constexpr long long kMaxCellsPerAxis = 1 << 16;
  for (int a = 0; a < 3; ++a) {
    if (resolution[a] > kMaxCellsPerAxis) {
      throw InvalidArgument("resolution must be at most " + std::to_string(kMaxCellsPerAxis) +
                            " cells per axis, got " + ivecText(resolution));
    }
  }
  fluid::Grid g;
  g.res = resolution;
  return fluid::fieldBytes(g);
}

// ---- checkpoint / restore (bake resume) -------------------------------------------------------

void Simulation::writeFloat(Field f, const std::vector<float>& data) {
  checkWritable(f, data.data(), data.size(), fieldShape(f));
  onGl([&](StepPipeline& e) { fieldTexture(e.fields(), f).upload(data.data(), data.size() * sizeof(float)); });
}

SimulationState Simulation::saveState() {
  SimulationState s;
  const std::pair<Field, BulkFloats*> fields[] = {
      {Field::VelocityX, &s.velocity_x}, {Field::VelocityY, &s.velocity_y},
      {Field::VelocityZ, &s.velocity_z}, {Field::Density, &s.density},
      {Field::Temperature, &s.temperature}, {Field::DynamicPressure, &s.dynamic_pressure}};
  for (const auto& [f, data] : fields) {
    const glm::ivec3 shape = fieldShape(f);
    data->resize(static_cast<std::size_t>(shape.x) * shape.y * shape.z);
  }
  // One GPU call for every field and the clock: a step from another thread (a HapticSession's)
  // comes wholly before or after the snapshot.
  onGl([&](StepPipeline& e) {
    for (const auto& [f, data] : fields) {
      fieldTexture(e.fields(), f).download(data->data(), data->size() * sizeof(float));
    }
    std::lock_guard<std::mutex> lock(state_mutex_);
    s.time_s = time_s_;
    s.steps = steps_;
  });
  return s;
}

void Simulation::restoreState(const SimulationState& s) {
  const std::pair<Field, const BulkFloats*> fields[] = {
      {Field::VelocityX, &s.velocity_x}, {Field::VelocityY, &s.velocity_y},
      {Field::VelocityZ, &s.velocity_z}, {Field::Density, &s.density},
      {Field::Temperature, &s.temperature}, {Field::DynamicPressure, &s.dynamic_pressure}};
  for (const auto& [f, data] : fields) checkWritable(f, data->data(), data->size(), fieldShape(f));
  if (!std::isfinite(s.time_s) || s.time_s < 0.0) {
    throw InvalidArgument("state time must be finite and >= 0 s, got " + num(s.time_s));
  }
  if (s.steps < 0) throw InvalidArgument("state step count must be >= 0, got " + std::to_string(s.steps));
  onGl([&](StepPipeline& e) {
    for (const auto& [f, data] : fields) {
      fieldTexture(e.fields(), f).upload(data->data(), data->size() * sizeof(float));
    }
    std::lock_guard<std::mutex> lock(state_mutex_);
    time_s_ = s.time_s;
    steps_ = s.steps;
    last_ = StepReport{};
  });
}

}  // namespace hf::session
