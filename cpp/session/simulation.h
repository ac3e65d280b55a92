// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The engine behind one narrow object. A Simulation owns a thread with its own compute device
// (compute::ComputeWorker: a GPU's GL context, or the CPU backend, session/backend_choice.h);
// every method posts its device work there and waits, so callers never touch the device.
// Public methods are safe to call from any one host thread at a time (they are serialised).
// Units are SI throughout.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/bulk_allocator.h"
#include "emitter/mesh_source.h"
#include "fluid/fluid_params.h"
#include "fluid/grid.h"
#include "compute/device.h"
#include "obstacle/sphere_probe.h"
#include "obstacle/triangle_mesh.h"

namespace hf::compute {
class ComputeWorker;
}

namespace hf::session {

class StepPipeline;

struct SimulationConfig {
  glm::ivec3 resolution{64, 64, 64};   // cells per axis (>= 8 each); cells must be cubic
  glm::vec3 domain_size_m{1.0f};       // box edge lengths, m
  glm::vec3 origin_m{0.0f};            // world position of the box's minimum corner, m
  fluid::FluidParams params;
  // The backend: "auto" (a hardware GPU if one gives a context, else the CPU), "gpu" (OpenGL on
  // the EGL device below, llvmpipe included), "cpu"; "" = HAPTICFLUID_BACKEND or auto.
  std::string backend;
  std::string device;                  // EGL device request ("" = HAPTICFLUID_EGL_DEVICE or auto)
  int cpu_threads = 0;                 // CPU backend's threads (0 = HAPTICFLUID_CPU_THREADS or one per core)
  // How much nicer (0..19, Linux niceness) the simulation's threads (its device thread and the GL
  // driver's or the CPU backend's pool) run
  // than the thread that makes the Simulation: 0 shares the cores equally; a live session beside
  // Blender's drawing on a CPU (llvmpipe) device asks for more, so the viewport keeps its pace.
  int thread_niceness = 0;
};

// The checks of a SimulationConfig that need no grid or device: the fluid's parameters and
// thread_niceness (the grid is checked when the Simulation is made).
void validate(const SimulationConfig& config);

struct StepReport {
  glm::vec3 force_n{0.0f};             // fluid force on the probe, N
  glm::vec3 torque_n_m{0.0f};          // fluid torque on the probe about torque_centre_m, N m
  glm::vec3 torque_centre_m{0.0f};     // the point used: asked for, or the voxelized centroid, m
  int exposed_faces = 0;               // faces summed into the force
  int solid_cells = 0;                 // cells the probe covers
  int pressure_iterations = 0;
  float relative_residual = -1.0f;     // ||rhs - A p|| / ||rhs|| after the solve; -1 = not measured
  float initial_relative_residual = -1.0f;  // the same before the solve (tolerance mode only, else -1)
  // Tolerance mode: the pressure solve reached pressure_tolerance within pressure_iterations
  // (always true in fixed-count mode).
  bool converged = true;
  // Set on the first step of this simulation whose solve did not converge (once per simulation),
  // else empty.
  std::string warning;
  double wall_ms = 0.0;                // host time of the whole step, ms
  std::vector<std::pair<std::string, double>> gpu_ms;  // GPU time per stage, ms
};

// Everything one step carries into the next (a checkpoint for resuming a bake): the MAC
// velocities, smoke, temperature, the dynamic pressure (the next solve's warm start) and the
// clock. Arrays are x fastest with the shapes of fieldShape(). Probe, source and settings are
// not part of it (they are inputs the caller sets before each step).
struct SimulationState {
  BulkFloats velocity_x, velocity_y, velocity_z;  // m/s on x-, y-, z-faces
  BulkFloats density;                             // smoke concentration
  BulkFloats temperature;                         // K above ambient
  BulkFloats dynamic_pressure;                    // Pa, without the hydrostatic part
  double time_s = 0.0;
  std::int64_t steps = 0;
};

// The probe as the host set it: a sphere, or a closed mesh with a rigid pose.
struct ProbeState {
  enum class Kind { Sphere, Mesh };
  Kind kind = Kind::Sphere;
  obstacle::SpherePose sphere;                          // Kind::Sphere
  std::shared_ptr<const obstacle::TriangleMesh> mesh;   // Kind::Mesh (shared, never changed)
  obstacle::MeshExtent extent;                          // of `mesh`, local frame
  obstacle::RigidPose pose;                             // Kind::Mesh
  std::optional<glm::vec3> torque_centre_m;             // world point; none: voxelized centroid
};

enum class Field { Density, Temperature, Pressure, DynamicPressure, VelocityX, VelocityY, VelocityZ, CellClass };

// Thread use: the setters and getters touch only host-side state under a short lock, so they
// never wait for the GPU; step(), reset(), the read-backs and close() run GPU work one at a
// time under a second lock. The state a step uses is copied when the step starts.
class Simulation {
 public:
  explicit Simulation(const SimulationConfig& config);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const compute::DeviceInfo& deviceInfo() const { return info_; }
  int threadNiceness() const { return thread_niceness_; }  // as made with (SimulationConfig)
  const fluid::Grid& grid() const { return grid_; }

  fluid::FluidParams params() const;
  void setParams(const fluid::FluidParams& params);
  // Edits a copy of the settings and applies it if it validates, as one atomic change.
  void updateParams(const std::function<void(fluid::FluidParams&)>& edit);
  // The sphere source (replaces a mesh source; a disabled one clears both).
  void setSmokeSource(const fluid::SmokeSource& source);
  fluid::SmokeSource smokeSource() const;
  // A closed mesh (local frame, m; checked like a mesh probe) posed by `transform` (local ->
  // world) as the smoke source, replacing any source (emitter/mesh_source.h); its mesh reaches
  // the GPU with the next step. Throws InvalidArgument and changes nothing on bad input.
  void setMeshSmokeSource(obstacle::TriangleMesh mesh, const glm::mat4& transform, float density,
                          float temperature_k, fluid::SourceEmission emission);
  // Moves the mesh source; O(1), never waits for the GPU. Throws InvalidArgument if there is
  // no mesh source or the pose is refused (emitter::validateSourcePose).
  void setSmokeSourcePose(const glm::mat4& transform);
  std::optional<emitter::MeshSource> meshSmokeSource() const;

  void setSphereProbe(const obstacle::SpherePose& pose);  // throws if not inside the domain
  // Validates and copies the mesh (closed, see obstacle/triangle_mesh.h) and the pose; the
  // mesh reaches the GPU with the next step. `torque_centre_m`: none = voxelized centroid.
  void setMeshProbe(obstacle::TriangleMesh mesh, const obstacle::RigidPose& pose,
                    const std::optional<glm::vec3>& torque_centre_m);
  // Moves the current probe (a sphere takes the translation as its centre); O(1), never waits
  // for the GPU. Throws InvalidArgument if there is no probe or the pose leaves the domain.
  void setProbePose(const obstacle::RigidPose& pose);
  void clearProbe();
  std::optional<obstacle::SpherePose> sphereProbe() const;  // the sphere, if the probe is one
  std::optional<ProbeState> probe() const;

  // Blocks until the step's force is read back. Throws InvalidArgument for a bad dt, and
  // hf::Error if the solver's state became non-finite (then reset() recovers).
  StepReport step(double dt_s);
  StepReport lastReport() const;
  double timeS() const;
  std::int64_t steps() const;
  void reset();  // fluid at rest, no smoke, time 0; probe and settings kept
  // Frees the GPU fields and ends the GL thread now; later GPU calls throw hf::Error.
  void close();
  bool closed() const { return closed_; }

  // Whole fields, x fastest (index = i + nx*(j + ny*k)). Face fields are (n+1) on their axis.
  glm::ivec3 fieldShape(Field f) const;
  std::vector<float> readFloat(Field f);
  std::vector<std::uint8_t> readCellClasses();
  // Overwrites one field (same shape and layout as readFloat); Pressure (it has the analytic
  // hydrostatic part) and CellClass (recomputed every step) are not writable: throws InvalidArgument.
  void writeFloat(Field f, const std::vector<float>& data);
  // Checkpoint and restore: restoring a saved state makes the following steps bit-identical to
  // those the saved simulation would have taken (same settings, probe and source). restoreState
  // checks every array's size and finiteness before it changes anything.
  SimulationState saveState();
  void restoreState(const SimulationState& state);

  // GPU memory the fields of a grid take, bytes; throws InvalidArgument for a bad resolution.
  static std::size_t estimateBytes(const glm::ivec3& resolution);
  // Bytes of the result read-back that ends every step (every result slot, vec4 each). With a
  // pressure tolerance > 0 the solver adds small residual read-backs while it iterates.
  static std::size_t stepReadbackBytes();

 private:
  // Runs fn(pipeline) on the GL thread, holding gpu_mutex_; throws if the simulation is closed.
  template <class F>
  auto onGl(F&& fn);

  fluid::Grid grid_;       // fixed at construction
  compute::DeviceInfo info_;   // fixed at construction

  // Host-side state, guarded by state_mutex_ (held only to copy in or out).
  mutable std::mutex state_mutex_;
  fluid::FluidParams params_;
  fluid::SmokeSource source_;
  std::optional<emitter::MeshSource> mesh_source_;  // set: it is the source (source_ disabled)
  std::optional<ProbeState> probe_;
  StepReport last_;
  bool warned_unconverged_ = false;  // StepReport::warning given once per simulation
  double time_s_ = 0.0;
  std::int64_t steps_ = 0;
  glm::vec3 last_rho_g_{0.0f};       // rho g of the last step (N/m^3), for pressure read-back
  glm::vec3 last_reference_m_{0.0f};  // where its hydrostatic pressure was 0

  // GPU side, guarded by gpu_mutex_.
  std::mutex gpu_mutex_;
  std::atomic<bool> closed_{false};
  std::unique_ptr<compute::ComputeWorker> worker_;
  int thread_niceness_ = 0;
  std::unique_ptr<StepPipeline> pipeline_;  // the device objects; lives and dies on the worker's thread
};

}  // namespace hf::session
