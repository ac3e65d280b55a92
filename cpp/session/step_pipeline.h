// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One simulation step on the GL thread, as a list of named stages: voxelize, classify, advect,
// emit, forces, divergence, pressure, residual (when asked for), project, force. Each stage ends with
// a GPU timer mark of its name (StepReport::gpu_ms); then the step's one read-back brings the
// force, torque, centroid and residual sums. Made, used and destroyed on the GL thread only
// (it holds GL objects); the Simulation copies the host state into StepInputs for it.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "fluid/fluid_params.h"
#include "fluid/fluid_solver.h"
#include "emitter/mesh_emitter.h"
#include "emitter/mesh_source.h"
#include "fluid/grid.h"
#include "force/force_reducer.h"
#include "compute/group_reducer.h"
#include "compute/stage_timer.h"
#include "obstacle/classifier.h"
#include "obstacle/mesh_probe.h"
#include "obstacle/sphere_probe.h"
#include "session/simulation.h"

namespace hf::session {

// What one step reads, copied from the host state when it starts.
struct StepInputs {
  float dt_s = 0.0f;                    // s, already checked (fluid::validateStep)
  fluid::FluidParams params;
  std::optional<ProbeState> probe;      // none: no body in the fluid
  fluid::SmokeSource source;             // the sphere source (enabled: emitting)
  std::optional<emitter::MeshSource> mesh_source;  // none: no mesh source
  glm::vec3 rho_g{0.0f};                // fluid density times gravity, N/m^3
  glm::vec3 reference_m{0.0f};          // world point of 0 hydrostatic pressure, m
};

class StepPipeline {
 public:
  // The step's read-back: this many vec4 result slots.
  static constexpr std::size_t kResultSlots = 5;

  explicit StepPipeline(const fluid::Grid& grid);
  ~StepPipeline();

  // Runs the stages in order and decodes the read-back. Throws hf::Error if the solver's state
  // became non-finite.
  StepReport step(const StepInputs& in);
  fluid::FluidFields& fields() { return solver_.fields(); }
  void reset() { solver_.reset(); }  // fluid at rest: velocity, smoke, heat, pressure zero

  // On (the default): a step that follows a step with the same kind of probe (a sphere, a mesh,
  // or none) and the same cut-cell and open-top settings voxelizes and classifies only the cells
  // the probe's move can change (its last and new bounds, grown by a cell), not the whole grid: the
  // solid mask, face fractions, classes and neighbour mask are the same to the bit. Off: every
  // step does the whole grid (the tests compare the two).
  void setLimitToProbeMoves(bool on) { limit_to_probe_moves_ = on; }

  // Called on the device thread around every stage that runs (tests compare the backends stage by
  // stage with it: tests/cpp/test_session_backends.cpp): before(name) may overwrite fields(),
  // after(name) may read them. Empty: none.
  struct StageHook {
    std::function<void(const char* stage)> before;
    std::function<void(const char* stage)> after;
  };
  void setStageHook(StageHook hook) { hook_ = std::move(hook); }
  // The stages in step order.
  static std::vector<const char*> stageNames();

 private:
  struct Pass;  // one step in flight: its inputs and what the stages hand on
  struct Stage {
    const char* name;                           // its GPU timer mark
    void (StepPipeline::*run)(Pass&);
    bool (*runs)(const fluid::FluidParams&);    // null: every step
  };
  static const Stage kStages[];

  void voxelize(Pass& pass);    // the probe writes the solid mask and velocity
  void classify(Pass& pass);    // face fractions; mask -> cell classes + neighbour mask
  void advect(Pass& pass);
  void emit(Pass& pass);        // the smoke source: sphere, or the mesh's coverage and emission
  void forces(Pass& pass);      // buoyancy, vorticity confinement
  void divergence(Pass& pass);  // boundaries, rhs (its mean removed in a closed box)
  void pressure(Pass& pass);    // the solve (its mean removed in a closed box)
  void residual(Pass& pass);    // ||rhs - A p||, ||rhs|| (FluidParams::compute_residual)
  void project(Pass& pass);
  void force(Pass& pass);       // force, torque, centroid over the body's cells
  StepReport report(const Pass& pass, const std::vector<glm::vec4>& results);  // + the finite check

  // What the last voxelize and classify were computed for: the next step may redo only what
  // its probe's move changes when this is the same but for the bounds.
  struct Footprint {
    enum class Body { None, Sphere, Mesh } body = Body::None;
    bool cut_cells = false;
    bool open_top = false;
    obstacle::CellBox bounds;  // the body's cells (empty for none)
  };
  obstacle::CellBox changedRegion(const Footprint& now) const;

  fluid::Grid grid_;
  std::optional<Footprint> footprint_;  // none before the first step
  bool limit_to_probe_moves_ = true;
  StageHook hook_;
  fluid::FluidSolver solver_;
  obstacle::SphereProbe sphere_;
  std::unique_ptr<obstacle::MeshProbe> mesh_;  // its programs made on first use
  std::unique_ptr<emitter::MeshEmitter> emitter_;  // made on first use (8 bytes per cell + coverage)
  obstacle::Classifier classifier_;
  force::ForceReducer force_;
  compute::GroupReducer reducer_;
  compute::StageTimer timer_;
};

}  // namespace hf::session
