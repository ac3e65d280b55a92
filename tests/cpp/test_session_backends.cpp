// SPDX-License-Identifier: GPL-3.0-or-later
// The two backends agree. Stage by stage: each stage of a step runs on the CPU backend from the
// GPU backend's fields before it, and must give the GPU's fields after it within float rounding
// (masks and classes exactly), from random states and from states of a real run, on odd grids,
// with a sphere and a mesh probe, both pressure solvers, both advection schemes. Whole steps:
// simulations on the two backends stay together. Threads: the CPU backend's results are the
// same to the bit on 1, 2 and 4 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/bulk_allocator.h"
#include "compute/compute_worker.h"
#include "cpu/cpu_device.h"
#include "cpu/kernel.h"
#include "emitter/mesh_source.h"
#include "fluid/fluid_fields.h"
#include "fluid/grid.h"
#include "gl/gl_device.h"
#include "mesh_shapes.h"
#include "session/simulation.h"
#include "session/step_pipeline.h"
#include "test_common.h"

namespace hf::session {
namespace {

// Float fields must agree to this share of their largest magnitude (float rounding: the
// backends' sums and the driver's contractions differ in the last bits).
constexpr double kStageTolerance = 1e-5;

// Every texture of the fields, by name (both textures of a ping-pong pair).
std::vector<std::pair<std::string, compute::Texture3D*>> textures(fluid::FluidFields& f) {
  std::vector<std::pair<std::string, compute::Texture3D*>> t;
  const char* axes[] = {"velocity x", "velocity y", "velocity z"};
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < 2; ++i) t.emplace_back(std::string(axes[a]) + (i ? " B" : " A"), &f.vel[a].tex[i]);
  }
  for (auto& [name, pp] : {std::pair<const char*, fluid::PingPong*>{"density", &f.density},
                           {"temperature", &f.temperature},
                           {"pressure", &f.pressure}}) {
    for (int i = 0; i < 2; ++i) t.emplace_back(std::string(name) + (i ? " B" : " A"), &pp->tex[i]);
  }
  t.emplace_back("rhs", &f.rhs);
  t.emplace_back("solid", &f.solid);
  t.emplace_back("solid velocity", &f.solid_velocity);
  t.emplace_back("cell class", &f.cell_class);
  t.emplace_back("neighbour mask", &f.nbmask);
  t.emplace_back("face open", &f.face_open);
  t.emplace_back("vorticity", &f.vorticity);
  t.emplace_back("cell force", &f.cell_force);
  return t;
}

using Snapshot = std::map<std::string, std::vector<std::uint8_t>>;

Snapshot snapshot(fluid::FluidFields& f) {
  Snapshot s;
  for (auto& [name, tex] : textures(f)) {
    std::vector<std::uint8_t> bytes(tex->texels() * tex->bytesPerTexel());
    tex->download(bytes.data(), bytes.size());
    s[name] = std::move(bytes);
  }
  return s;
}

void restore(fluid::FluidFields& f, const Snapshot& s) {
  for (auto& [name, tex] : textures(f)) {
    const auto& bytes = s.at(name);
    tex->upload(bytes.data(), bytes.size());
  }
}

// The worst disagreement of one field: max |a - b| / max |a| for floats, count of differing
// bytes for integer textures.
struct Difference {
  double relative = 0.0;
  double max_abs = 0.0;
  long long bytes_differ = 0;
};

Difference compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, bool floats) {
  Difference d;
  if (!floats) {
    for (std::size_t i = 0; i < a.size(); ++i) d.bytes_differ += a[i] != b[i];
    return d;
  }
  const std::size_t n = a.size() / sizeof(float);
  std::vector<float> fa(n), fb(n);
  std::memcpy(fa.data(), a.data(), a.size());
  std::memcpy(fb.data(), b.data(), b.size());
  double scale = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    scale = std::max(scale, static_cast<double>(std::fabs(fa[i])));
    const double e = std::fabs(static_cast<double>(fa[i]) - static_cast<double>(fb[i]));
    worst = std::isnan(e) ? INFINITY : std::max(worst, e);
  }
  d.max_abs = scale;
  d.relative = scale > 0.0 ? worst / scale : worst;
  return d;
}

bool isFloatTexture(const std::string& name) {
  return name != "solid" && name != "cell class" && name != "neighbour mask";
}

// A scene: the grid and every step's inputs.
struct Scene {
  std::string name;
  fluid::Grid grid;
  StepInputs in;
};

fluid::Grid grid(const glm::ivec3& res) {
  fluid::Grid g;
  g.res = res;
  g.cell_size_m = 1.0f / static_cast<float>(res.x);
  return g;
}

Scene sphereScene(const glm::ivec3& res) {
  Scene s{"sphere " + std::to_string(res.x) + "x" + std::to_string(res.y) + "x" + std::to_string(res.z), grid(res), {}};
  const glm::vec3 size = s.grid.sizeM();
  StepInputs& in = s.in;
  in.dt_s = 1.0f / 30.0f;
  in.params.open_top = false;
  in.params.cut_cells = true;
  in.params.advection = fluid::Advection::MacCormack;
  in.params.vorticity_confinement = 0.3f;
  in.params.heat_buoyancy_m_s2_k = 0.5f;
  in.params.smoke_weight_m_s2 = 0.1f;
  in.params.density_dissipation_1_s = 0.05f;
  in.params.pressure_solver = fluid::PressureSolverKind::Multigrid;
  in.params.pressure_iterations = 8;
  in.params.pressure_tolerance = 1e-3f;
  in.source.enabled = true;
  in.source.centre_m = glm::vec3(0.5f * size.x, 0.45f * size.y, 0.2f * size.z);
  in.source.radius_m = 0.15f * std::min(size.x, std::min(size.y, size.z));
  in.source.temperature_k = 4.0f;
  in.rho_g = glm::vec3(0.0f, 0.0f, -9.81f * in.params.density_kg_m3);
  ProbeState p;
  p.kind = ProbeState::Kind::Sphere;
  p.sphere.centre_m = glm::vec3(0.45f * size.x, 0.5f * size.y, 0.55f * size.z);
  p.sphere.radius_m = 0.2f * std::min(size.x, std::min(size.y, size.z));
  p.sphere.velocity_m_s = glm::vec3(0.3f, -0.1f, 0.05f);
  p.sphere.angular_velocity_rad_s = glm::vec3(0.0f, 1.0f, 2.0f);
  in.probe = p;
  return s;
}

Scene meshScene(const glm::ivec3& res) {
  Scene s{"mesh " + std::to_string(res.x) + "x" + std::to_string(res.y) + "x" + std::to_string(res.z), grid(res), {}};
  const glm::vec3 size = s.grid.sizeM();
  StepInputs& in = s.in;
  in.dt_s = 1.0f / 24.0f;
  in.params.open_top = true;
  in.params.cut_cells = true;
  in.params.advection = fluid::Advection::SemiLagrangian;
  in.params.heat_buoyancy_m_s2_k = 1.0f;
  in.params.pressure_solver = fluid::PressureSolverKind::Jacobi;
  in.params.pressure_iterations = 12;
  in.params.density_kg_m3 = 1000.0f;
  in.rho_g = glm::vec3(0.0f, 0.0f, -9.81f * in.params.density_kg_m3);
  const float l = std::min(size.x, std::min(size.y, size.z));
  in.mesh_source = emitter::makeMeshSource(test::boxMesh(glm::vec3(-0.125f * l), glm::vec3(0.125f * l)),
                                           glm::translate(glm::mat4(1.0f), glm::vec3(0.3f * size.x, 0.5f * size.y, 0.2f * size.z)),
                                           1.0f, 3.0f, fluid::SourceEmission::Rate, s.grid);
  ProbeState p;
  p.kind = ProbeState::Kind::Mesh;
  p.mesh = std::make_shared<const obstacle::TriangleMesh>(test::boxMesh(-glm::vec3(0.15f * l, 0.1f * l, 0.125f * l), glm::vec3(0.15f * l, 0.1f * l, 0.125f * l)));
  p.extent = obstacle::meshExtent(*p.mesh);
  p.pose.transform = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.6f * size.x, 0.5f * size.y, 0.5f * size.z)),
                                 0.4f, glm::vec3(0.2f, 0.3f, 1.0f));
  p.pose.velocity_m_s = glm::vec3(-0.2f, 0.1f, 0.0f);
  p.pose.angular_velocity_rad_s = glm::vec3(0.5f, 0.0f, 1.0f);
  in.probe = p;
  return s;
}

// A random but plausible state: smooth velocity (m/s) plus noise, smoke and heat in 0..1,
// pressure (Pa) of the size the scene's flows make.
void randomState(fluid::FluidFields& f, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
  auto fill = [&](compute::Texture3D& t, float smooth, float amplitude, float offset) {
    const glm::ivec3 n = t.size();
    std::vector<float> v(t.texels());
    std::size_t i = 0;
    for (int z = 0; z < n.z; ++z) {
      for (int y = 0; y < n.y; ++y) {
        for (int x = 0; x < n.x; ++x, ++i) {
          v[i] = offset + amplitude * (smooth * std::sin(0.3f * x + 0.2f * y - 0.4f * z) + 0.3f * noise(rng));
        }
      }
    }
    t.upload(v.data(), v.size() * sizeof(float));
  };
  for (auto& pp : f.vel) fill(pp.cur(), 1.0f, 0.5f, 0.0f);
  fill(f.density.cur(), 0.5f, 0.5f, 0.5f);
  fill(f.temperature.cur(), 0.5f, 2.0f, 2.0f);
  fill(f.pressure.cur(), 1.0f, 3.0f, 0.0f);
}

struct StageResult {
  std::string stage;
  std::string worst_field;
  double relative = 0.0;
  long long bytes_differ = 0;
};

// Runs one step on the GPU pipeline recording its fields around each stage, then the same step
// on the CPU pipeline, each stage started from the GPU's fields before it; returns each stage's
// worst field. The state both start from: `warm_steps` real steps, then (seed != 0) random fields.
std::vector<StageResult> compareStages(const Scene& scene, int warm_steps, unsigned random_seed) {
  gl::GlWorker gpu;
  cpu::CpuWorker cpu_worker;
  std::map<std::string, Snapshot> before, after;
  std::vector<std::string> order;
  gpu.call([&] {
    StepPipeline p(scene.grid);
    for (int s = 0; s < warm_steps; ++s) p.step(scene.in);
    if (random_seed != 0) randomState(p.fields(), random_seed);
    StepPipeline::StageHook hook;
    hook.before = [&](const char* stage) { before[stage] = snapshot(p.fields()); };
    hook.after = [&](const char* stage) {
      after[stage] = snapshot(p.fields());
      order.emplace_back(stage);
    };
    p.setStageHook(hook);
    p.step(scene.in);
  });
  std::vector<StageResult> results;
  cpu_worker.call([&] {
    StepPipeline p(scene.grid);
    // The same history: the CPU pipeline's footprint (which cells the probe's move redoes)
    // must match, so it steps as often before.
    for (int s = 0; s < warm_steps; ++s) p.step(scene.in);
    StepPipeline::StageHook hook;
    hook.before = [&](const char* stage) { restore(p.fields(), before.at(stage)); };
    hook.after = [&](const char* stage) {
      const Snapshot mine = snapshot(p.fields());
      StageResult r{stage, "", 0.0, 0};
      for (const auto& [name, bytes] : after.at(stage)) {
        const Difference d = compare(bytes, mine.at(name), isFloatTexture(name));
        if (d.relative > r.relative || (d.bytes_differ > 0 && r.relative == 0.0)) r.worst_field = name;
        r.relative = std::max(r.relative, d.relative);
        r.bytes_differ += d.bytes_differ;
      }
      results.push_back(r);
    };
    p.setStageHook(hook);
    p.step(scene.in);
  });
  EXPECT_EQ(results.size(), order.size());
  return results;
}

void expectStagesAgree(const Scene& scene, int warm_steps, unsigned seed) {
  const std::vector<StageResult> results = compareStages(scene, warm_steps, seed);
  ASSERT_FALSE(results.empty());
  for (const StageResult& r : results) {
    EXPECT_EQ(r.bytes_differ, 0) << scene.name << ", stage " << r.stage << ": masks or classes differ";
    EXPECT_LE(r.relative, kStageTolerance) << scene.name << ", stage " << r.stage << ": " << r.worst_field;
    // The figure the closing note quotes (stage, worst relative difference of its fields).
    std::printf("AGREEMENT %s %s stage %-10s worst %-16s %.2e\n", scene.name.c_str(),
                seed != 0 ? "random" : "real", r.stage.c_str(),
                r.worst_field.empty() ? "(all equal)" : r.worst_field.c_str(), r.relative);
  }
}

TEST(BackendsAgree, EveryStageOfARealStepWithASphereOnAnOddGrid) {
  expectStagesAgree(sphereScene({17, 13, 11}), 6, 0);
}

TEST(BackendsAgree, EveryStageFromARandomStateWithASphere) {
  expectStagesAgree(sphereScene({33, 20, 9}), 1, 1234);
}

TEST(BackendsAgree, EveryStageOfARealStepWithAMeshProbeAndSource) {
  expectStagesAgree(meshScene({24, 21, 18}), 5, 0);
}

TEST(BackendsAgree, EveryStageFromARandomStateWithAMesh) {
  expectStagesAgree(meshScene({48, 48, 48}), 1, 99);
}

// ---- whole simulations ------------------------------------------------------------------

SimulationConfig config(const std::string& backend, int threads, const glm::ivec3& cells) {
  SimulationConfig c;
  c.resolution = cells;
  c.domain_size_m = glm::vec3(cells) / static_cast<float>(cells.x);
  c.backend = backend;
  c.cpu_threads = threads;
  c.params.advection = fluid::Advection::MacCormack;
  c.params.vorticity_confinement = 0.2f;
  c.params.heat_buoyancy_m_s2_k = 1.0f;
  c.params.pressure_solver = fluid::PressureSolverKind::Multigrid;
  c.params.pressure_tolerance = 1e-3f;
  return c;
}

struct Trajectory {
  std::vector<glm::vec3> forces;
  SimulationState state;
};

const glm::ivec3 kAgreementCells(32, 28, 24);

Trajectory run(const std::string& backend, int threads, int steps, const glm::ivec3& cells = kAgreementCells) {
  Simulation sim(config(backend, threads, cells));
  fluid::SmokeSource src;
  src.enabled = true;
  src.centre_m = glm::vec3(0.5f, 0.4f, 0.15f);
  src.radius_m = 0.1f;
  src.temperature_k = 3.0f;
  sim.setSmokeSource(src);
  Trajectory r;
  for (int s = 0; s < steps; ++s) {
    obstacle::SpherePose pose;
    pose.centre_m = glm::vec3(0.3f + 0.02f * static_cast<float>(s), 0.45f, 0.4f);
    pose.radius_m = 0.12f;
    pose.velocity_m_s = glm::vec3(0.6f, 0.0f, 0.0f);
    sim.setSphereProbe(pose);
    r.forces.push_back(sim.step(1.0 / 30.0).force_n);
  }
  r.state = sim.saveState();
  return r;
}

double relativeDifference(const BulkFloats& a, const BulkFloats& b) {
  double scale = 0.0, worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    scale = std::max(scale, static_cast<double>(std::fabs(a[i])));
    worst = std::max(worst, std::fabs(static_cast<double>(a[i]) - static_cast<double>(b[i])));
  }
  return scale > 0.0 ? worst / scale : worst;
}

TEST(BackendsAgree, TwelveWholeStepsStayTogether) {
  const Trajectory gpu = run("gpu", 0, 12);
  const Trajectory cpu = run("cpu", 0, 12);
  for (std::size_t s = 0; s < gpu.forces.size(); ++s) {
    const float scale = glm::length(gpu.forces[s]);
    EXPECT_LE(glm::length(gpu.forces[s] - cpu.forces[s]), 1e-3f * scale + 1e-6f) << "step " << s;
  }
  const std::pair<const char*, double> fields[] = {
      {"velocity x", relativeDifference(gpu.state.velocity_x, cpu.state.velocity_x)},
      {"velocity y", relativeDifference(gpu.state.velocity_y, cpu.state.velocity_y)},
      {"velocity z", relativeDifference(gpu.state.velocity_z, cpu.state.velocity_z)},
      {"density", relativeDifference(gpu.state.density, cpu.state.density)},
      {"temperature", relativeDifference(gpu.state.temperature, cpu.state.temperature)},
      {"pressure", relativeDifference(gpu.state.dynamic_pressure, cpu.state.dynamic_pressure)}};
  for (const auto& [name, rel] : fields) {
    EXPECT_LE(rel, 1e-4) << name;
    std::printf("AGREEMENT 12 steps %-12s %.2e\n", name, rel);
  }
}

// On a grid whose finest level's dispatches are split over the threads (at least
// kSerialInvocations cells; the coarse levels and small dispatches run on the calling thread).
TEST(CpuBackend, ResultsAreTheSameToTheBitOnOneTwoAndFourThreads) {
  const glm::ivec3 cells(48, 44, 40);
  static_assert(48LL * 44 * 40 >= cpu::kSerialInvocations, "a grid the CPU splits over its threads");
  const Trajectory one = run("cpu", 1, 6, cells);
  for (int threads : {2, 4}) {
    const Trajectory other = run("cpu", threads, 6, cells);
    for (std::size_t s = 0; s < one.forces.size(); ++s) {
      EXPECT_EQ(std::memcmp(&one.forces[s], &other.forces[s], sizeof(glm::vec3)), 0)
          << threads << " threads, step " << s;
    }
    EXPECT_EQ(one.state.velocity_x, other.state.velocity_x) << threads << " threads";
    EXPECT_EQ(one.state.velocity_y, other.state.velocity_y) << threads << " threads";
    EXPECT_EQ(one.state.velocity_z, other.state.velocity_z) << threads << " threads";
    EXPECT_EQ(one.state.density, other.state.density) << threads << " threads";
    EXPECT_EQ(one.state.temperature, other.state.temperature) << threads << " threads";
    EXPECT_EQ(one.state.dynamic_pressure, other.state.dynamic_pressure) << threads << " threads";
  }
}

// The baseline and the x86-64-v3 (AVX2) builds of the loops give the same bits: a whole step of
// every stage (moving sphere, source, MacCormack, vorticity, multigrid) from the same state.
TEST(CpuBackend, BaselineAndAvx2BuildsGiveTheSameBits) {
  if (!cpu::cpuHasX86V3()) GTEST_SKIP() << "this CPU has no AVX2 (or HAPTICFLUID_CPU_ISA=baseline)";
  const Scene scene = sphereScene({33, 20, 17});
  std::map<bool, Snapshot> after;
  for (bool v3 : {false, true}) {
    cpu::CpuWorker worker(2, std::nullopt, v3);
    worker.call([&] {
      StepPipeline p(scene.grid);
      for (int s = 0; s < 4; ++s) p.step(scene.in);
      after[v3] = snapshot(p.fields());
    });
  }
  for (const auto& [name, bytes] : after[false]) EXPECT_EQ(bytes, after[true].at(name)) << name;
}

// The same from a random state (displacements up to about a cell, with noise): the AVX2 build
// advects in blocks that read a window of rows (one row and slice for every lane, or three of
// each) and falls back to the shader's lookup where a block strays or its window would leave the
// field (cpu/kernels/advect.cpp); the baseline build looks up every texel as the shader does.
TEST(CpuBackend, BaselineAndAvx2BuildsGiveTheSameBitsFromARandomState) {
  if (!cpu::cpuHasX86V3()) GTEST_SKIP() << "this CPU has no AVX2 (or HAPTICFLUID_CPU_ISA=baseline)";
  for (const Scene& scene : {sphereScene({37, 22, 19}), meshScene({29, 26, 21})}) {
    std::map<bool, Snapshot> after;
    for (bool v3 : {false, true}) {
      cpu::CpuWorker worker(2, std::nullopt, v3);
      worker.call([&] {
        StepPipeline p(scene.grid);
        p.step(scene.in);
        randomState(p.fields(), 4321);
        p.step(scene.in);
        after[v3] = snapshot(p.fields());
      });
    }
    for (const auto& [name, bytes] : after[false]) EXPECT_EQ(bytes, after[true].at(name)) << scene.name << ": " << name;
  }
}

}  // namespace
}  // namespace hf::session
