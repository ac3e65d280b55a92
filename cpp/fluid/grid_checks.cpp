// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/grid_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/error.h"
#include "common/format.h"
#include "fluid/fluid_fields.h"
#include "fluid/validate.h"

namespace hf::fluid {
namespace {

constexpr int kMinCells = 8;          // per axis: stencils and walls need room
constexpr double kMemoryShare = 0.8;  // of the device's memory the fields may take

}  // namespace

void checkResolution(const glm::ivec3& r) {
  for (int a = 0; a < 3; ++a) {
    if (r[a] < kMinCells) {
      throw InvalidArgument("resolution must be at least " + std::to_string(kMinCells) +
                            " cells on every axis, got " + ivecText(r));
    }
  }
}

Grid makeGrid(const glm::ivec3& resolution, const glm::vec3& domain_size_m, const glm::vec3& origin_m) {
  checkResolution(resolution);
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(domain_size_m[a]) || domain_size_m[a] <= 0.0f) {
      throw InvalidArgument("domain size must be positive and finite on every axis (m), got " +
                            vecText(domain_size_m));
    }
    if (!std::isfinite(origin_m[a]) || std::fabs(origin_m[a]) > kMaxOriginOffset) {
      throw InvalidArgument("domain origin must be finite and within " + num(kMaxOriginOffset) +
                            " m of the world origin (float precision), got " + vecText(origin_m));
    }
  }
  const glm::vec3 h = domain_size_m / glm::vec3(resolution);
  const float h0 = h.x;
  for (int a = 1; a < 3; ++a) {
    if (std::fabs(h[a] - h0) > 1e-4f * h0) {
      throw InvalidArgument("cells must be cubic: domain size / resolution gives cell edges " + vecText(h) +
                            " m; choose a resolution proportional to the domain size, e.g. (" +
                            std::to_string(resolution.x) + ", " +
                            std::to_string(std::lround(domain_size_m.y / h0)) + ", " +
                            std::to_string(std::lround(domain_size_m.z / h0)) + ")");
    }
  }
  if (h0 < kMinCellSize || h0 > kMaxCellSize) {
    throw InvalidArgument("cell size " + num(h0) + " m is outside " + num(kMinCellSize) + " .. " +
                          num(kMaxCellSize) + " m; change the domain size or the resolution");
  }
  Grid g;
  g.res = resolution;
  g.cell_size_m = h0;
  g.origin_m = origin_m;
  return g;
}

void checkFits(const Grid& g, const compute::DeviceInfo& info) {
  const long long largest = static_cast<long long>(std::max(g.res.x, std::max(g.res.y, g.res.z))) + 1;  // faces: n+1
  if (info.max_3d_texture_size > 0 && largest > info.max_3d_texture_size) {
    throw InvalidArgument("resolution too large for this GPU: " + std::to_string(largest) +
                          " texels on an axis, the device allows " + std::to_string(info.max_3d_texture_size));
  }
  const std::size_t need = fieldBytes(g);
  if (info.memory_bytes > 0 && static_cast<double>(need) > kMemoryShare * static_cast<double>(info.memory_bytes)) {
    throw InvalidArgument("resolution too large for this GPU's memory: the fields need " +
                          std::to_string(need >> 20) + " MiB, the device (" + info.renderer + ") has " +
                          std::to_string(info.memory_bytes >> 20) + " MiB; lower the resolution");
  }
}

float pressureToleranceFloor(const Grid& g) {
  const int n = std::max(g.res.x, std::max(g.res.y, g.res.z));
  return std::numeric_limits<float>::epsilon() * static_cast<float>(n) / 16.0f;
}

void checkPressureTolerance(const FluidParams& p, const Grid& g) {
  const float floor = pressureToleranceFloor(g);
  if (p.pressure_tolerance != 0.0f && p.pressure_tolerance < floor) {
    // The floor rounded up to two significant digits: a value the user can type that passes.
    const double step = std::pow(10.0, std::floor(std::log10(static_cast<double>(floor))) - 1.0);
    const double suggest = std::ceil(static_cast<double>(floor) / step) * step;
    throw InvalidArgument("pressure tolerance " + num(p.pressure_tolerance) + " is below what float32 can reach on a " +
                          std::to_string(g.res.x) + "x" + std::to_string(g.res.y) + "x" + std::to_string(g.res.z) +
                          " grid (relative residual floor " + num(floor) + "); use at least " + num(suggest) +
                          ", or 0 for a fixed number of iterations");
  }
}

void validateStep(double dt_s, const FluidParams& p, const Grid& g) {
  checkPressureTolerance(p, g);
  if (!std::isfinite(dt_s) || dt_s < kMinTimeStep || dt_s > kMaxTimeStep) {
    throw InvalidArgument("time step must be between " + num(kMinTimeStep) + " and " + num(kMaxTimeStep) +
                          " s, got " + num(dt_s) + " s");
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

}  // namespace hf::fluid
