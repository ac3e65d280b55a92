// SPDX-License-Identifier: GPL-3.0-or-later
// Simulation checkpoint: saveState/restoreState continue bit-identically; bad states are refused
// before anything changes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>
#include <string>

#include "common/bulk_allocator.h"
#include "common/error.h"
#include "session/simulation.h"

namespace hf::session {
namespace {

SimulationConfig plumeConfig() {
  SimulationConfig c;
  c.resolution = glm::ivec3(16);
  c.params.heat_buoyancy_m_s2_k = 1.5f;
  c.params.vorticity_confinement = 0.3f;
  c.params.pressure_iterations = 12;
  return c;
}

void prepare(Simulation& s) {
  fluid::SmokeSource src;
  src.enabled = true;
  src.centre_m = glm::vec3(0.5f, 0.5f, 0.2f);
  src.radius_m = 0.15f;
  src.density = 1.0f;
  src.temperature_k = 6.0f;
  s.setSmokeSource(src);
}

void run(Simulation& s, int from, int to) {
  for (int i = from; i < to; ++i) {
    obstacle::SpherePose p;
    p.centre_m = glm::vec3(0.3f + 0.03f * i, 0.5f, 0.5f);
    p.radius_m = 0.12f;
    p.velocity_m_s = glm::vec3(0.75f, 0.0f, 0.0f);
    s.setSphereProbe(p);
    s.step(0.04);
  }
}

TEST(SimulationState, RestoreContinuesBitIdentically) {
  Simulation a(plumeConfig()), b(plumeConfig());
  prepare(a);
  prepare(b);
  run(a, 0, 4);
  const SimulationState saved = a.saveState();
  EXPECT_EQ(saved.steps, 4);
  run(a, 4, 8);
  b.restoreState(saved);
  EXPECT_EQ(b.steps(), 4);
  EXPECT_DOUBLE_EQ(b.timeS(), saved.time_s);
  run(b, 4, 8);
  const SimulationState sa = a.saveState(), sb = b.saveState();
  EXPECT_EQ(sa.velocity_x, sb.velocity_x);
  EXPECT_EQ(sa.velocity_y, sb.velocity_y);
  EXPECT_EQ(sa.velocity_z, sb.velocity_z);
  EXPECT_EQ(sa.density, sb.density);
  EXPECT_EQ(sa.temperature, sb.temperature);
  EXPECT_EQ(sa.dynamic_pressure, sb.dynamic_pressure);
  float max_density = 0.0f;
  for (float d : sa.density) max_density = std::max(max_density, d);
  EXPECT_GT(max_density, 0.5f);
}

TEST(SimulationState, BadStatesAreRefusedBeforeAnythingChanges) {
  Simulation s(plumeConfig());
  prepare(s);
  run(s, 0, 2);
  const SimulationState good = s.saveState();
  SimulationState bad = good;
  bad.velocity_y.pop_back();
  try {
    s.restoreState(bad);
    FAIL() << "a short velocity y was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("velocity y needs 4352 values"), std::string::npos) << e.what();
  }
  bad = good;
  bad.density[0] = NAN;
  EXPECT_THROW(s.restoreState(bad), InvalidArgument);
  bad = good;
  bad.time_s = -1.0;
  EXPECT_THROW(s.restoreState(bad), InvalidArgument);
  EXPECT_EQ(s.saveState().density, good.density);  // nothing changed
  const std::vector<float> density(good.density.begin(), good.density.end());
  EXPECT_THROW(s.writeFloat(Field::Pressure, density), InvalidArgument);
  EXPECT_THROW(s.writeFloat(Field::CellClass, density), InvalidArgument);
  std::vector<float> ones(good.density.size(), 1.0f);
  s.writeFloat(Field::Temperature, ones);
  EXPECT_EQ(s.readFloat(Field::Temperature), ones);
}

// The state's arrays (common/bulk_allocator.h): one of the seed grid's fields (2.8 MB) and a small
// one keep what is written through resizes, copies and moves; a freed large block is handed to the
// next array of its size, and the pool keeps no more than its cap.
TEST(SimulationState, BulkArraysKeepWhatIsWrittenAndReuseFreedBlocks) {
  for (const std::size_t n : {std::size_t{100 * 100 * 70}, std::size_t{17 * 17 * 17}}) {
    BulkFloats a;
    a.resize(n);
    for (std::size_t i = 0; i < n; ++i) a[i] = static_cast<float>(i) * 0.5f;
    BulkFloats copy = a;
    EXPECT_EQ(copy, a);
    a.resize(2 * n);  // reallocates: the old values move over
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(a[i], static_cast<float>(i) * 0.5f) << i;
    a[2 * n - 1] = -1.0f;
    EXPECT_EQ(a[2 * n - 1], -1.0f);
    BulkFloats moved = std::move(copy);
    EXPECT_EQ(moved[n - 1], static_cast<float>(n - 1) * 0.5f);
  }
  const std::size_t n = 100 * 100 * 70;
  const float* first = nullptr;
  {
    BulkFloats a(n, 1.0f);
    first = a.data();
  }
  BulkFloats again;
  again.resize(n);
  EXPECT_EQ(again.data(), first);  // the freed block, not a fresh mapping
  {
    BulkFloats huge((kBulkPoolBytes + 4096) / sizeof(float), 2.0f);
    EXPECT_EQ(huge.back(), 2.0f);
  }
  EXPECT_LE(detail::BulkPool::instance().heldBytes(), kBulkPoolBytes);
}

}  // namespace
}  // namespace hf::session
