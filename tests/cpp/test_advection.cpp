// SPDX-License-Identifier: GPL-3.0-or-later
// Semi-Lagrangian advection (advect.comp) against a CPU reference on a small odd grid with a
// random velocity field: the midpoint back-trace with clamp-to-edge trilinear lookups, for the
// three velocity components and for smoke and heat carried together (their decay and the
// zeroing of solid cells included). The shader takes the trace's first velocity from 1, 2 or 4
// texels at the sample point instead of a full lookup; this checks that it is the same value.
// MacCormack (maccormack.comp) against the same reference: its correction and limiter trace
// back exactly as advect.comp does (the velocity interpolated from images, no texture()).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "fluid/fluid_solver.h"
#include "test_util.h"

namespace hf::fluid {
namespace {

struct Field {
  glm::ivec3 n;
  std::vector<float> v;
  float at(glm::ivec3 c) const { return v[static_cast<std::size_t>(c.x + n.x * (c.y + n.y * c.z))]; }
  // Trilinear at texel-space t, clamped to the edge (GL_LINEAR + GL_CLAMP_TO_EDGE).
  double sample(glm::dvec3 t) const {
    t = glm::clamp(t, glm::dvec3(0.0), glm::dvec3(n - 1));
    const glm::ivec3 i0(t);
    const glm::dvec3 f = t - glm::dvec3(i0);
    const glm::ivec3 i1 = glm::min(i0 + 1, n - 1);
    double sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::ivec3 c((corner & 1) ? i1.x : i0.x, (corner & 2) ? i1.y : i0.y, (corner & 4) ? i1.z : i0.z);
      const double w = ((corner & 1) ? f.x : 1.0 - f.x) * ((corner & 2) ? f.y : 1.0 - f.y) *
                       ((corner & 4) ? f.z : 1.0 - f.z);
      sum += w * at(c);
    }
    return sum;
  }
};

class AdvectionTest : public test::DeviceTest {};

TEST_F(AdvectionTest, MidpointBackTraceMatchesCpuReference) {
  Grid grid;
  grid.res = {11, 9, 7};
  grid.cell_size_m = 0.1f;
  const float dt = 0.05f;  // with |v| <= 3 m/s: up to 1.5 cells per step, so traces leave the grid
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> velocity(-3.0f, 3.0f), scalar(0.0f, 1.0f);

  std::array<Field, 3> vel;
  for (int a = 0; a < 3; ++a) {
    vel[a].n = grid.faceSize(a);
    vel[a].v.resize(static_cast<std::size_t>(vel[a].n.x) * vel[a].n.y * vel[a].n.z);
    for (float& x : vel[a].v) x = velocity(rng);
  }
  Field smoke{grid.res, std::vector<float>(grid.cells())}, heat{grid.res, std::vector<float>(grid.cells())};
  for (float& x : smoke.v) x = scalar(rng);
  for (float& x : heat.v) x = 300.0f * scalar(rng);
  std::vector<std::uint8_t> mask(grid.cells(), 0);
  const glm::ivec3 solid_cell(5, 4, 3);
  mask[static_cast<std::size_t>(solid_cell.x + grid.res.x * (solid_cell.y + grid.res.y * solid_cell.z))] = 128;

  FluidParams params;
  params.density_dissipation_1_s = 0.5f;
  params.temperature_dissipation_1_s = 2.0f;

  std::array<std::vector<float>, 5> gpu;  // u, v, w, smoke, heat after the step
  onGl([&] {
    FluidSolver solver(grid);
    FluidFields& f = solver.fields();
    for (int a = 0; a < 3; ++a) f.vel[a].cur().upload(vel[a].v.data(), vel[a].v.size() * sizeof(float));
    f.density.cur().upload(smoke.v.data(), smoke.v.size() * sizeof(float));
    f.temperature.cur().upload(heat.v.data(), heat.v.size() * sizeof(float));
    f.nbmask.upload(mask.data(), mask.size());
    solver.advect(dt, params);
    for (int a = 0; a < 3; ++a) {
      gpu[a].resize(vel[a].v.size());
      f.vel[a].cur().download(gpu[a].data(), gpu[a].size() * sizeof(float));
    }
    gpu[3].resize(grid.cells());
    gpu[4].resize(grid.cells());
    f.density.cur().download(gpu[3].data(), gpu[3].size() * sizeof(float));
    f.temperature.cur().download(gpu[4].data(), gpu[4].size() * sizeof(float));
  });

  const double dt_over_h = double(dt) / grid.cell_size_m;
  auto velocityAt = [&](const glm::dvec3& X) {
    glm::dvec3 u;
    for (int a = 0; a < 3; ++a) u[a] = vel[a].sample(X - glm::dvec3(Grid::faceOffset(a)));
    return u;
  };
  auto advected = [&](const Field& src, const glm::dvec3& offset, const glm::ivec3& idx) {
    const glm::dvec3 X = glm::dvec3(idx) + offset;
    const glm::dvec3 mid = X - 0.5 * dt_over_h * velocityAt(X);
    const glm::dvec3 back = glm::clamp(X - dt_over_h * velocityAt(mid), glm::dvec3(0.0), glm::dvec3(grid.res));
    return src.sample(back - offset);
  };

  int checked = 0;
  for (int field = 0; field < 5; ++field) {
    const bool scalar_field = field >= 3;
    const Field& src = field < 3 ? vel[field] : field == 3 ? smoke : heat;
    const glm::dvec3 offset = scalar_field ? glm::dvec3(0.5) : glm::dvec3(Grid::faceOffset(field));
    const double decay = field == 3 ? std::exp(-0.5 * dt) : field == 4 ? std::exp(-2.0 * dt) : 1.0;
    const double scale = field == 4 ? 300.0 : field == 3 ? 1.0 : 3.0;
    for (int k = 0; k < src.n.z; ++k)
      for (int j = 0; j < src.n.y; ++j)
        for (int i = 0; i < src.n.x; ++i) {
          const glm::ivec3 idx(i, j, k);
          const float got = gpu[field][static_cast<std::size_t>(i + src.n.x * (j + src.n.y * k))];
          const double want = scalar_field && idx == solid_cell ? 0.0 : decay * advected(src, offset, idx);
          ASSERT_NEAR(got, want, 2e-5 * scale) << "field " << field << " at " << i << "," << j << "," << k;
          ++checked;
        }
  }
  EXPECT_EQ(checked, 12 * 9 * 7 + 11 * 10 * 7 + 11 * 9 * 8 + 2 * 11 * 9 * 7);
}

TEST_F(AdvectionTest, MacCormackMatchesCpuReference) {
  Grid grid;
  grid.res = {9, 8, 7};
  grid.cell_size_m = 0.1f;
  const float dt = 0.05f;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> velocity(-3.0f, 3.0f), scalar(0.0f, 1.0f);
  std::array<Field, 3> vel;
  for (int a = 0; a < 3; ++a) {
    vel[a].n = grid.faceSize(a);
    vel[a].v.resize(static_cast<std::size_t>(vel[a].n.x) * vel[a].n.y * vel[a].n.z);
    for (float& x : vel[a].v) x = velocity(rng);
  }
  Field smoke{grid.res, std::vector<float>(grid.cells())};
  for (float& x : smoke.v) x = scalar(rng);
  Field heat{grid.res, std::vector<float>(grid.cells(), 0.0f)};
  std::vector<std::uint8_t> mask(grid.cells(), 0);
  const glm::ivec3 solid_cell(4, 3, 2);
  mask[static_cast<std::size_t>(solid_cell.x + grid.res.x * (solid_cell.y + grid.res.y * solid_cell.z))] = 128;
  FluidParams params;
  params.advection = Advection::MacCormack;
  params.density_dissipation_1_s = 0.5f;

  std::array<std::vector<float>, 4> gpu;  // u, v, w, smoke
  onGl([&] {
    FluidSolver solver(grid);
    FluidFields& f = solver.fields();
    for (int a = 0; a < 3; ++a) f.vel[a].cur().upload(vel[a].v.data(), vel[a].v.size() * sizeof(float));
    f.density.cur().upload(smoke.v.data(), smoke.v.size() * sizeof(float));
    f.temperature.cur().upload(heat.v.data(), heat.v.size() * sizeof(float));
    f.nbmask.upload(mask.data(), mask.size());
    solver.advect(dt, params);
    for (int a = 0; a < 3; ++a) {
      gpu[a].resize(vel[a].v.size());
      f.vel[a].cur().download(gpu[a].data(), gpu[a].size() * sizeof(float));
    }
    gpu[3].resize(grid.cells());
    f.density.cur().download(gpu[3].data(), gpu[3].size() * sizeof(float));
  });

  auto velocityAt = [&](const glm::dvec3& X) {
    glm::dvec3 u;
    for (int a = 0; a < 3; ++a) u[a] = vel[a].sample(X - glm::dvec3(Grid::faceOffset(a)));
    return u;
  };
  auto backPoint = [&](const glm::dvec3& offset, const glm::ivec3& idx, double dt_over_h) {
    const glm::dvec3 X = glm::dvec3(idx) + offset;
    const glm::dvec3 mid = X - 0.5 * dt_over_h * velocityAt(X);
    return glm::clamp(X - dt_over_h * velocityAt(mid), glm::dvec3(0.0), glm::dvec3(grid.res)) - offset;
  };
  auto pass = [&](const Field& src, const glm::dvec3& offset, double dt_over_h) {
    Field out{src.n, std::vector<float>(src.v.size())};
    for (int k = 0; k < src.n.z; ++k)
      for (int j = 0; j < src.n.y; ++j)
        for (int i = 0; i < src.n.x; ++i) {
          out.v[static_cast<std::size_t>(i + src.n.x * (j + src.n.y * k))] =
              static_cast<float>(src.sample(backPoint(offset, {i, j, k}, dt_over_h)));
        }
    return out;
  };
  const double dt_over_h = double(dt) / grid.cell_size_m;
  int checked = 0;
  for (int field = 0; field < 4; ++field) {
    const Field& phi = field < 3 ? vel[field] : smoke;
    const glm::dvec3 offset = field == 3 ? glm::dvec3(0.5) : glm::dvec3(Grid::faceOffset(field));
    const double decay = field == 3 ? std::exp(-0.5 * dt) : 1.0;
    const double scale = field == 3 ? 1.0 : 3.0;
    const Field fwd = pass(phi, offset, dt_over_h);
    const Field bwd = pass(fwd, offset, -dt_over_h);
    for (int k = 0; k < phi.n.z; ++k)
      for (int j = 0; j < phi.n.y; ++j)
        for (int i = 0; i < phi.n.x; ++i) {
          const glm::ivec3 idx(i, j, k);
          const glm::dvec3 t = backPoint(offset, idx, dt_over_h);
          const glm::ivec3 base = glm::clamp(glm::ivec3(glm::floor(t)), glm::ivec3(0), phi.n - 1);
          double lo = 1e30, hi = -1e30;
          for (int n = 0; n < 8; ++n) {
            const glm::ivec3 q = glm::min(base + glm::ivec3(n & 1, (n >> 1) & 1, (n >> 2) & 1), phi.n - 1);
            lo = std::min(lo, double(phi.at(q)));
            hi = std::max(hi, double(phi.at(q)));
          }
          const double corrected = double(fwd.at(idx)) + 0.5 * (double(phi.at(idx)) - double(bwd.at(idx)));
          const double want = field == 3 && idx == solid_cell ? 0.0 : std::clamp(corrected, lo, hi) * decay;
          const float got = gpu[field][static_cast<std::size_t>(i + phi.n.x * (j + phi.n.y * k))];
          ASSERT_NEAR(got, want, 5e-5 * scale) << "field " << field << " at " << i << "," << j << "," << k;
          ++checked;
        }
  }
  EXPECT_EQ(checked, 10 * 8 * 7 + 9 * 9 * 7 + 9 * 8 * 8 + 9 * 8 * 7);
}

}  // namespace
}  // namespace hf::fluid
