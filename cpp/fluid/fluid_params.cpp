// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/fluid_params.h"

#include <cmath>
#include <string>

#include "common/error.h"
#include "common/format.h"
#include "fluid/validate.h"

namespace hf::fluid {
namespace {

void requireFinite(float v, const char* name) {
  if (!std::isfinite(v)) throw InvalidArgument(std::string(name) + " must be a finite number, got " + num(v));
}

void requireInRange(float v, float lo, float hi, const char* name, const char* unit) {
  requireFinite(v, name);
  if (v < lo || v > hi) {
    throw InvalidArgument(std::string(name) + " must be between " + num(lo) + " and " + num(hi) + " " + unit +
                          ", got " + num(v));
  }
}

void requireInRange(float v, const Range& r, const char* name, const char* unit) {
  requireInRange(v, static_cast<float>(r.min), static_cast<float>(r.max), name, unit);
}

}  // namespace

void validate(const FluidParams& p) {
  requireFinite(p.density_kg_m3, "fluid density");
  if (p.density_kg_m3 < kFluidDensityRange.min || p.density_kg_m3 > kFluidDensityRange.max) {
    throw InvalidArgument("fluid density must be between " + num(kFluidDensityRange.min) + " and " +
                          num(kFluidDensityRange.max) + " kg/m^3 (air is 1.2, water 1000), got " + num(p.density_kg_m3));
  }
  for (int a = 0; a < 3; ++a) requireFinite(p.gravity_m_s2[a], "gravity (m/s^2)");
  if (glm::length(p.gravity_m_s2) > kMaxGravity) {
    throw InvalidArgument("gravity must be at most " + num(kMaxGravity) + " m/s^2 in magnitude, got " +
                          vecText(p.gravity_m_s2));
  }
  if (p.open_top && (p.gravity_m_s2.x != 0.0f || p.gravity_m_s2.y != 0.0f || p.gravity_m_s2.z > 0.0f)) {
    throw InvalidArgument("an open top needs gravity along -z (or none): the opening must be a surface of "
                          "constant pressure; got gravity " + vecText(p.gravity_m_s2) + " m/s^2");
  }
  requireInRange(p.vorticity_confinement, kVorticityRange, "vorticity confinement", "(dimensionless)");
  requireInRange(p.smoke_weight_m_s2, kSmokeWeightRange, "smoke weight", "m/s^2");
  requireInRange(p.heat_buoyancy_m_s2_k, kHeatBuoyancyRange, "heat buoyancy", "m/s^2/K");
  requireInRange(p.density_dissipation_1_s, kDissipationRange, "smoke dissipation", "1/s");
  requireInRange(p.temperature_dissipation_1_s, kDissipationRange, "heat dissipation", "1/s");
  if (p.pressure_iterations < kPressureIterationsRange.min || p.pressure_iterations > kPressureIterationsRange.max) {
    throw InvalidArgument("pressure iterations must be between " + num(kPressureIterationsRange.min) + " and " +
                          num(kPressureIterationsRange.max) + ", got " + std::to_string(p.pressure_iterations));
  }
  requireFinite(p.pressure_tolerance, "pressure tolerance");
  if (p.pressure_tolerance != 0.0f &&
      (p.pressure_tolerance < kMinPressureTolerance || p.pressure_tolerance >= kPressureToleranceRange.max)) {
    throw InvalidArgument("pressure tolerance (relative residual, dimensionless) must be 0 (run a fixed number of "
                          "iterations) or between " + num(kMinPressureTolerance) + " and " +
                          num(kPressureToleranceRange.max) + " (exclusive), got " + num(p.pressure_tolerance));
  }
  if (p.pressure_solver != PressureSolverKind::Jacobi && p.pressure_solver != PressureSolverKind::Multigrid) {
    throw InvalidArgument("pressure solver must be Jacobi or Multigrid");
  }
}

void validate(const SmokeSource& s, const Grid& g) {
  if (!s.enabled) return;
  for (int a = 0; a < 3; ++a) requireFinite(s.centre_m[a], "smoke source centre (m)");
  requireFinite(s.radius_m, "smoke source radius (m)");
  if (s.radius_m <= 0.0f) throw InvalidArgument("smoke source radius must be > 0 m, got " + num(s.radius_m));
  validateSourceValues(s.density, s.temperature_k, s.emission);
  const glm::vec3 lo = g.origin_m, hi = g.origin_m + g.sizeM();
  if (glm::any(glm::lessThan(s.centre_m + s.radius_m, lo)) || glm::any(glm::greaterThan(s.centre_m - s.radius_m, hi))) {
    throw InvalidArgument("smoke source lies entirely outside the domain; move its centre inside the box");
  }
}

void validateSourceValues(float density, float temperature_k, SourceEmission emission) {
  if (emission != SourceEmission::Hold && emission != SourceEmission::Rate) {
    throw InvalidArgument("smoke source emission must be Hold or Rate");
  }
  const bool rate = emission == SourceEmission::Rate;
  requireInRange(density, 0.0f, kMaxFactor, "smoke source density",
                 rate ? "(concentration per second)" : "(concentration)");
  requireInRange(temperature_k, 0.0f, kMaxTemperature, "smoke source temperature",
                 rate ? "K per second" : "K above ambient");
}

}  // namespace hf::fluid
