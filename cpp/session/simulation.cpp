#include "session/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "common/error.h"
#include "common/finite.h"
#include "common/format.h"
#include "fluid/fluid_solver.h"
#include "fluid/row_reduction.h"
#include "fluid/validate.h"
#include "force/force_reducer.h"
#include "gl/gl_worker.h"
#include "gl/group_reducer.h"
#include "gl/stage_timer.h"
#include "gl/workgroup.h"
#include "obstacle/cell_class.h"
#include "obstacle/classifier.h"
#include "obstacle/mesh_probe.h"

namespace hf::session {
namespace {

constexpr int kMinCells = 8;           // per axis: stencils and walls need room
constexpr double kMemoryShare = 0.8;   // of the device's memory the fields may take
constexpr std::size_t kForceSlot = 0;
constexpr std::size_t kResidualSlot = 1;
constexpr std::size_t kPressureMeanSlot = 2;
constexpr std::size_t kTorqueSlot = 3;
constexpr std::size_t kCentroidSlot = 4;
constexpr std::size_t kResultSlots = 5;
constexpr force::ForceSlots kForceSlots{kForceSlot, kTorqueSlot, kCentroidSlot};

std::string resText(const glm::ivec3& r) {
  return "(" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.z) + ")";
}

void checkResolution(const glm::ivec3& r) {
  for (int a = 0; a < 3; ++a) {
    if (r[a] < kMinCells) {
      throw InvalidArgument("resolution must be at least " + std::to_string(kMinCells) +
                            " cells on every axis, got " + resText(r));
    }
  }
}

fluid::Grid makeGrid(const SimulationConfig& c) {
  checkResolution(c.resolution);
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(c.domain_size_m[a]) || c.domain_size_m[a] <= 0.0f) {
      throw InvalidArgument("domain size must be positive and finite on every axis (m), got " +
                            vecText(c.domain_size_m));
    }
    if (!std::isfinite(c.origin_m[a]) || std::fabs(c.origin_m[a]) > fluid::kMaxOriginOffset) {
      throw InvalidArgument("domain origin must be finite and within " + num(fluid::kMaxOriginOffset) +
                            " m of the world origin (float precision), got " + vecText(c.origin_m));
    }
  }
  const glm::vec3 h = c.domain_size_m / glm::vec3(c.resolution);
  const float h0 = h.x;
  for (int a = 1; a < 3; ++a) {
    if (std::fabs(h[a] - h0) > 1e-4f * h0) {
      throw InvalidArgument("cells must be cubic: domain size / resolution gives cell edges " + vecText(h) +
                            " m; choose a resolution proportional to the domain size, e.g. (" +
                            std::to_string(c.resolution.x) + ", " +
                            std::to_string(std::lround(c.domain_size_m.y / h0)) + ", " +
                            std::to_string(std::lround(c.domain_size_m.z / h0)) + ")");
    }
  }
  if (h0 < fluid::kMinCellSize || h0 > fluid::kMaxCellSize) {
    throw InvalidArgument("cell size " + num(h0) + " m is outside " + num(fluid::kMinCellSize) + " .. " +
                          num(fluid::kMaxCellSize) + " m; change the domain size or the resolution");
  }
  fluid::Grid g;
  g.res = c.resolution;
  g.cell_size_m = h0;
  g.origin_m = c.origin_m;
  return g;
}

void checkFits(const fluid::Grid& g, const gl::ContextInfo& info) {
  const long long largest = static_cast<long long>(std::max(g.res.x, std::max(g.res.y, g.res.z))) + 1;  // faces: n+1
  if (info.max_3d_texture_size > 0 && largest > info.max_3d_texture_size) {
    throw InvalidArgument("resolution too large for this GPU: " + std::to_string(largest) +
                          " texels on an axis, the device allows " + std::to_string(info.max_3d_texture_size));
  }
  const std::size_t need = fluid::fieldBytes(g);
  if (info.memory_bytes > 0 && static_cast<double>(need) > kMemoryShare * static_cast<double>(info.memory_bytes)) {
    throw InvalidArgument("resolution too large for this GPU's memory: the fields need " +
                          std::to_string(need >> 20) + " MiB, the device (" + info.renderer + ") has " +
                          std::to_string(info.memory_bytes >> 20) + " MiB; lower the resolution");
  }
}

// World point where the hydrostatic pressure is zero: the domain's highest point against gravity.
glm::vec3 hydrostaticReference(const fluid::Grid& g, const glm::vec3& gravity) {
  glm::vec3 ref = g.origin_m + 0.5f * g.sizeM();
  for (int a = 0; a < 3; ++a) {
    if (gravity[a] < 0.0f) ref[a] = g.origin_m[a] + g.sizeM()[a];
    if (gravity[a] > 0.0f) ref[a] = g.origin_m[a];
  }
  return ref;
}

void validateMotion(const glm::vec3& velocity_m_s, const glm::vec3& angular_velocity_rad_s) {
  if (!allFinite(velocity_m_s) || !allFinite(angular_velocity_rad_s)) {
    throw InvalidArgument("probe motion must be finite: velocity " + vecText(velocity_m_s) +
                          " m/s, angular velocity " + vecText(angular_velocity_rad_s) + " rad/s");
  }
  if (glm::length(velocity_m_s) > fluid::kMaxProbeSpeed) {
    throw InvalidArgument("probe speed must be at most " + num(fluid::kMaxProbeSpeed) + " m/s, got " +
                          vecText(velocity_m_s) + " m/s");
  }
  if (glm::length(angular_velocity_rad_s) > fluid::kMaxProbeSpin) {
    throw InvalidArgument("probe angular speed must be at most " + num(fluid::kMaxProbeSpin) + " rad/s, got " +
                          vecText(angular_velocity_rad_s) + " rad/s");
  }
}

void validatePose(const obstacle::SpherePose& p, const fluid::Grid& g) {
  if (!allFinite(p.centre_m)) {
    throw InvalidArgument("probe pose must be finite: centre " + vecText(p.centre_m) + " m");
  }
  validateMotion(p.velocity_m_s, p.angular_velocity_rad_s);
  if (!std::isfinite(p.radius_m) || p.radius_m < g.cell_size_m) {
    throw InvalidArgument("probe radius must be at least one cell (" + num(g.cell_size_m) +
                          " m) to be seen by the grid, got " + num(p.radius_m) + " m; raise the radius or the resolution");
  }
  // At least one whole fluid cell between the body and every wall, so the faces summed into the
  // force enclose it and the force does not depend on the pressure's arbitrary constant.
  const glm::vec3 lo = g.origin_m + g.cell_size_m, hi = g.origin_m + g.sizeM() - g.cell_size_m;
  const std::string what = "probe sphere (centre " + vecText(p.centre_m) + " m, radius " + num(p.radius_m) +
                           " m) is not inside the domain with at least one cell (" + num(g.cell_size_m) +
                           " m) of fluid between it and every wall";
  if (glm::any(glm::greaterThan(lo + p.radius_m, hi - p.radius_m))) {
    throw InvalidArgument(what + "; with this radius it cannot fit: the radius must be at most " +
                          num(0.5f * glm::min(glm::min(g.sizeM().x, g.sizeM().y), g.sizeM().z) - g.cell_size_m) + " m");
  }
  if (glm::any(glm::lessThan(p.centre_m - p.radius_m, lo)) || glm::any(glm::greaterThan(p.centre_m + p.radius_m, hi))) {
    throw InvalidArgument(what + "; its centre must stay within " + vecText(lo + p.radius_m) + " .. " +
                          vecText(hi - p.radius_m) + " m");
  }
}

// The mesh's world box (conservative, see obstacle::worldBox) must keep one whole fluid cell
// from every wall, like the sphere.
void validatePose(const obstacle::MeshExtent& extent, const obstacle::RigidPose& p, const fluid::Grid& g) {
  obstacle::validateTransform(p.transform);
  validateMotion(p.velocity_m_s, p.angular_velocity_rad_s);
  const double visits = obstacle::columnVisitBound(extent, p.transform, g.cell_size_m);
  if (!(visits <= obstacle::kMaxColumnVisits)) {
    throw InvalidArgument("the posed mesh's triangles could cover up to " + num(visits) +
                          " cell columns per step (limit " + num(obstacle::kMaxColumnVisits) +
                          "); split its large triangles, scale it down or use a coarser grid");
  }
  const obstacle::WorldBox box = obstacle::worldBox(extent, p.transform);
  const glm::vec3 lo = g.origin_m + g.cell_size_m, hi = g.origin_m + g.sizeM() - g.cell_size_m;
  if (glm::any(glm::lessThan(box.lo, lo)) || glm::any(glm::greaterThan(box.hi, hi))) {
    throw InvalidArgument("the posed mesh (bounds " + vecText(box.lo) + " .. " + vecText(box.hi) +
                          " m) is not inside the domain with at least one cell (" + num(g.cell_size_m) +
                          " m) of fluid between it and every wall: keep it within " + vecText(lo) + " .. " +
                          vecText(hi) + " m (move it, scale it down, or enlarge the domain)");
  }
}

// In double, so a value float cannot hold (1e-40, 1e300) is reported as given.
void validateStep(double dt_s, const fluid::FluidParams& p, const fluid::Grid& g) {
  if (!std::isfinite(dt_s) || dt_s < fluid::kMinTimeStep || dt_s > fluid::kMaxTimeStep) {
    throw InvalidArgument("time step must be between " + num(fluid::kMinTimeStep) + " and " +
                          num(fluid::kMaxTimeStep) + " s, got " + num(dt_s) + " s");
  }
  // The scales the stages use must be ordinary floats (no overflow or underflow).
  const float dt = static_cast<float>(dt_s);
  const float to_pa = p.density_kg_m3 * g.cell_size_m / dt;
  const float to_velocity = dt / (p.density_kg_m3 * g.cell_size_m);
  if (!std::isnormal(to_pa) || !std::isnormal(to_velocity)) {
    throw InvalidArgument("time step " + num(dt_s) + " s with fluid density " + num(p.density_kg_m3) +
                          " kg/m^3 and cell size " + num(g.cell_size_m) + " m is outside float range");
  }
}

}  // namespace

// Everything that holds GL objects; made, used and destroyed on the worker thread only.
struct Simulation::Engine {
  explicit Engine(const fluid::Grid& g)
      : grid(g), solver(g), probe(g), classifier(g), force(g),
        reducer(std::max(force::ForceReducer::partialsNeeded(g), fluid::rowCount(g.res)),
                kResultSlots) {}

  StepReport step(float dt, const fluid::FluidParams& p, const std::optional<ProbeState>& pose,
                  const fluid::SmokeSource& source, const glm::vec3& rho_g, const glm::vec3& /*reference_m: the force takes only hydrostatic differences*/) {
    auto& f = solver.fields();
    timer.begin();
    obstacle::Obstacle* body = nullptr;
    if (pose && pose->kind == ProbeState::Kind::Sphere) {
      probe.setPose(pose->sphere);
      probe.setCutCells(p.cut_cells);
      body = &probe;
    } else if (pose) {
      if (!mesh_probe) mesh_probe = std::make_unique<obstacle::MeshProbe>(grid);  // its programs on first use
      mesh_probe->setMesh(pose->mesh);
      mesh_probe->setPose(pose->pose);
      body = mesh_probe.get();
    }
    if (body) {
      body->voxelize(f.solid, f.solid_velocity);
    } else {
      f.solid.clear();
      f.solid_velocity.clear();
    }
    timer.mark("voxelize");
    const bool cut_cells = body && body->writeFaceFractions(f.face_open);
    if (!cut_cells) classifier.binaryFractions(f.solid, f.face_open);
    classifier.classify(f.solid, f.face_open, f.cell_class, f.nbmask, p.open_top);
    timer.mark("classify");
    solver.advect(dt, p);
    timer.mark("advect");
    solver.applySources(source);
    solver.applyForces(dt, p);
    timer.mark("forces");
    solver.enforceBoundaries(p);
    solver.computeDivergence(dt, p);
    if (!p.open_top) solver.removeRhsMean(reducer, kPressureMeanSlot);  // compatibility condition
    timer.mark("divergence");
    const fluid::SolveStats stats = solver.solvePressure(p);
    if (!p.open_top) solver.removePressureMean(reducer, kPressureMeanSlot);
    timer.mark("pressure");
    if (p.compute_residual) {
      solver.measureResidual(reducer, kResidualSlot);
      timer.mark("residual");
    }
    solver.project(dt, p);
    timer.mark("project");
    const obstacle::CellBox box = body ? body->bounds() : obstacle::CellBox{};
    const glm::vec3 p0 = body ? body->referencePointM() : glm::vec3(0.0f);
    force.reduce(f.pressure.cur(), f.cell_class, f.nbmask, f.face_open, box, cut_cells, rho_g, p0, reducer, kForceSlots);
    timer.mark("force");
    const std::vector<glm::vec4> results = reducer.readResults();  // the step's one read-back
    StepReport r;
    const force::BodyForce bf =
        force::ForceReducer::decode(results, kForceSlots, p0, pose ? pose->torque_centre_m : std::nullopt);
    r.force_n = bf.force_n;
    r.torque_n_m = bf.torque_n_m;
    r.torque_centre_m = bf.torque_centre_m;
    r.exposed_faces = bf.exposed_faces;
    r.solid_cells = bf.solid_cells;
    r.pressure_iterations = stats.iterations;
    r.initial_relative_residual = stats.initial_relative_residual;
    if (p.compute_residual) {
      const glm::vec4 res = results[kResidualSlot];
      r.relative_residual = fluid::relativeResidual(res.x, res.y);
    } else {
      r.relative_residual = stats.relative_residual;  // the solver's own estimate in tolerance mode, else -1
    }
    r.gpu_ms = timer.collect();
    const glm::vec4 mean = results[kPressureMeanSlot];
    if (!allFinite(r.force_n) || !allFinite(r.torque_n_m) ||
        (p.compute_residual && !std::isfinite(r.relative_residual)) || (!p.open_top && !std::isfinite(mean.x))) {
      throw Error("the solver's state became non-finite (force " + vecText(r.force_n) +
                  " N); call reset() and use a smaller time step or probe speed");
    }
    return r;
  }

  fluid::Grid grid;
  fluid::FluidSolver solver;
  obstacle::SphereProbe probe;
  std::unique_ptr<obstacle::MeshProbe> mesh_probe;
  obstacle::Classifier classifier;
  force::ForceReducer force;
  gl::GroupReducer reducer;
  gl::StageTimer timer;
};

std::size_t Simulation::stepReadbackBytes() { return kResultSlots * sizeof(glm::vec4); }

Simulation::Simulation(const SimulationConfig& config) : grid_(makeGrid(config)), params_(config.params) {
  fluid::validate(params_);
  worker_ = std::make_unique<gl::GlWorker>(config.device);
  info_ = worker_->info();
  checkFits(grid_, info_);
  engine_ = worker_->call([this] { return std::make_unique<Engine>(grid_); });
  last_rho_g_ = params_.density_kg_m3 * params_.gravity_m_s2;
  last_reference_m_ = hydrostaticReference(grid_, params_.gravity_m_s2);
}

Simulation::~Simulation() { close(); }

template <class F>
auto Simulation::onGl(F&& fn) {
  std::lock_guard<std::mutex> lock(gpu_mutex_);
  if (!engine_) throw Error("this simulation was closed; make a new one");
  return worker_->call([&] { return fn(*engine_); });
}

void Simulation::close() {
  std::lock_guard<std::mutex> lock(gpu_mutex_);
  if (worker_ && engine_) {
    try {
      worker_->call([this] { engine_.reset(); });
    } catch (...) {
      // Closing must not throw. GL objects may only die on the GL thread, so if that failed
      // they are abandoned here and freed with the context when the worker ends.
      static_cast<void>(engine_.release());
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
  std::lock_guard<std::mutex> lock(state_mutex_);
  params_ = params;
}

void Simulation::setSmokeSource(const fluid::SmokeSource& source) {
  fluid::validate(source, grid_);
  std::lock_guard<std::mutex> lock(state_mutex_);
  source_ = source;
}

void Simulation::updateParams(const std::function<void(fluid::FluidParams&)>& edit) {
  std::lock_guard<std::mutex> lock(state_mutex_);
  fluid::FluidParams p = params_;
  edit(p);
  fluid::validate(p);
  params_ = p;
}

fluid::SmokeSource Simulation::smokeSource() const {
  std::lock_guard<std::mutex> lock(state_mutex_);
  return source_;
}

void Simulation::setSphereProbe(const obstacle::SpherePose& pose) {
  validatePose(pose, grid_);
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
  validatePose(state.extent, pose, grid_);
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
    validatePose(sphere, grid_);
    probe_->sphere = sphere;
  } else {
    validatePose(probe_->extent, pose, grid_);
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
  fluid::FluidParams params;
  fluid::SmokeSource source;
  std::optional<ProbeState> pose;
  {
    std::lock_guard<std::mutex> lock(state_mutex_);
    params = params_;
    source = source_;
    pose = probe_;
  }
  validateStep(dt_in_s, params, grid_);
  const float dt_s = static_cast<float>(dt_in_s);
  const glm::vec3 rho_g = params.density_kg_m3 * params.gravity_m_s2;
  const glm::vec3 reference = hydrostaticReference(grid_, params.gravity_m_s2);
  const auto t0 = std::chrono::steady_clock::now();
  StepReport r = onGl([&](Engine& e) {
    StepReport out = e.step(dt_s, params, pose, source, rho_g, reference);
    // Under the GPU lock with the fields it describes: a saveState() sees both or neither.
    std::lock_guard<std::mutex> lock(state_mutex_);
    time_s_ += dt_s;
    ++steps_;
    return out;
  });
  r.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::lock_guard<std::mutex> lock(state_mutex_);
  last_ = r;
  last_rho_g_ = rho_g;
  last_reference_m_ = reference;
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
  onGl([](Engine& e) { e.solver.reset(); });
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
gl::Texture3D& fieldTexture(fluid::FluidFields& fl, Field f) {
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

void checkWritable(Field f, const std::vector<float>& data, const glm::ivec3& shape) {
  if (f == Field::Pressure || f == Field::CellClass) {
    throw InvalidArgument(std::string(fieldName(f)) +
                          " cannot be written: write the dynamic pressure (the hydrostatic part is analytic); "
                          "cell classes are recomputed every step");
  }
  const std::size_t n = static_cast<std::size_t>(shape.x) * shape.y * shape.z;
  if (data.size() != n) {
    throw InvalidArgument(std::string(fieldName(f)) + " needs " + std::to_string(n) + " values (shape " +
                          resText(shape) + "), got " + std::to_string(data.size()));
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
  onGl([&](Engine& e) {
    auto& fl = e.solver.fields();
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
  onGl([&](Engine& e) { e.solver.fields().cell_class.download(out.data(), out.size()); });
  return out;
}

std::size_t Simulation::estimateBytes(const glm::ivec3& resolution) {
  checkResolution(resolution);
  constexpr long long kMaxCellsPerAxis = 1 << 16;
  for (int a = 0; a < 3; ++a) {
    if (resolution[a] > kMaxCellsPerAxis) {
      throw InvalidArgument("resolution must be at most " + std::to_string(kMaxCellsPerAxis) +
                            " cells per axis, got " + resText(resolution));
    }
  }
  fluid::Grid g;
  g.res = resolution;
  return fluid::fieldBytes(g);
}

// ---- checkpoint / restore (bake resume) -------------------------------------------------------

void Simulation::writeFloat(Field f, const std::vector<float>& data) {
  checkWritable(f, data, fieldShape(f));
  onGl([&](Engine& e) { fieldTexture(e.solver.fields(), f).upload(data.data(), data.size() * sizeof(float)); });
}

SimulationState Simulation::saveState() {
  SimulationState s;
  const std::pair<Field, std::vector<float>*> fields[] = {
      {Field::VelocityX, &s.velocity_x}, {Field::VelocityY, &s.velocity_y},
      {Field::VelocityZ, &s.velocity_z}, {Field::Density, &s.density},
      {Field::Temperature, &s.temperature}, {Field::DynamicPressure, &s.dynamic_pressure}};
  for (const auto& [f, data] : fields) {
    const glm::ivec3 shape = fieldShape(f);
    data->resize(static_cast<std::size_t>(shape.x) * shape.y * shape.z);
  }
  // One GPU call for every field and the clock: a step from another thread (a HapticSession's)
  // comes wholly before or after the snapshot.
  onGl([&](Engine& e) {
    for (const auto& [f, data] : fields) {
      fieldTexture(e.solver.fields(), f).download(data->data(), data->size() * sizeof(float));
    }
    std::lock_guard<std::mutex> lock(state_mutex_);
    s.time_s = time_s_;
    s.steps = steps_;
  });
  return s;
}

void Simulation::restoreState(const SimulationState& s) {
  const std::pair<Field, const std::vector<float>*> fields[] = {
      {Field::VelocityX, &s.velocity_x}, {Field::VelocityY, &s.velocity_y},
      {Field::VelocityZ, &s.velocity_z}, {Field::Density, &s.density},
      {Field::Temperature, &s.temperature}, {Field::DynamicPressure, &s.dynamic_pressure}};
  for (const auto& [f, data] : fields) checkWritable(f, *data, fieldShape(f));
  if (!std::isfinite(s.time_s) || s.time_s < 0.0) {
    throw InvalidArgument("state time must be finite and >= 0 s, got " + num(s.time_s));
  }
  if (s.steps < 0) throw InvalidArgument("state step count must be >= 0, got " + std::to_string(s.steps));
  onGl([&](Engine& e) {
    for (const auto& [f, data] : fields) {
      fieldTexture(e.solver.fields(), f).upload(data->data(), data->size() * sizeof(float));
    }
    std::lock_guard<std::mutex> lock(state_mutex_);
    time_s_ = s.time_s;
    steps_ = s.steps;
    last_ = StepReport{};
  });
}

}  // namespace hf::session
