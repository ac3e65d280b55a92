#include "fluid/fluid_params.h"

#include <cmath>
#include <string>

#include "common/error.h"
#include "fluid/validate.h"

namespace hf::fluid {
namespace {

void requireFinite(float v, const char* name) {
  if (!std::isfinite(v)) throw InvalidArgument(std::string(name) + " must be a finite number, got " + std::to_string(v));
}

void requireNonNegative(float v, const char* name, const char* unit) {
  requireFinite(v, name);
  if (v < 0.0f) {
    throw InvalidArgument(std::string(name) + " must be >= 0 " + unit + ", got " + std::to_string(v));
  }
}

}  // namespace

void validate(const FluidParams& p) {
  requireFinite(p.density_kg_m3, "fluid density");
  if (p.density_kg_m3 <= 0.0f) {
    throw InvalidArgument("fluid density must be > 0 kg/m^3 (air is 1.2, water 1000), got " +
                          std::to_string(p.density_kg_m3));
  }
  for (int a = 0; a < 3; ++a) requireFinite(p.gravity_m_s2[a], "gravity (m/s^2)");
  requireNonNegative(p.vorticity_confinement, "vorticity confinement", "(dimensionless)");
  requireFinite(p.smoke_weight_m_s2, "smoke weight (m/s^2)");
  requireFinite(p.heat_buoyancy_m_s2_k, "heat buoyancy (m/s^2/K)");
  requireNonNegative(p.density_dissipation_1_s, "smoke dissipation", "1/s");
  requireNonNegative(p.temperature_dissipation_1_s, "heat dissipation", "1/s");
  if (p.pressure_iterations < 1 || p.pressure_iterations > kMaxPressureIterations) {
    throw InvalidArgument("pressure iterations must be between 1 and " + std::to_string(kMaxPressureIterations) +
                          ", got " + std::to_string(p.pressure_iterations));
  }
}

void validate(const SmokeSource& s, const Grid& g) {
  if (!s.enabled) return;
  for (int a = 0; a < 3; ++a) requireFinite(s.centre_m[a], "smoke source centre (m)");
  requireFinite(s.radius_m, "smoke source radius (m)");
  if (s.radius_m <= 0.0f) throw InvalidArgument("smoke source radius must be > 0 m, got " + std::to_string(s.radius_m));
  requireNonNegative(s.density, "smoke source density", "(concentration)");
  requireNonNegative(s.temperature_k, "smoke source temperature", "K above ambient");
  const glm::vec3 lo = g.origin_m, hi = g.origin_m + g.sizeM();
  if (glm::any(glm::lessThan(s.centre_m + s.radius_m, lo)) || glm::any(glm::greaterThan(s.centre_m - s.radius_m, hi))) {
    throw InvalidArgument("smoke source lies entirely outside the domain; move its centre inside the box");
  }
}

}  // namespace hf::fluid
