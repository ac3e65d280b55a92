// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Checks of user-supplied settings; each throws hf::InvalidArgument saying what to change.
// The ranges keep every derived quantity (rho h / dt, rho g L, face forces) a normal float;
// they are wide enough for any smoke or liquid a person can move a probe through.
#include "common/range.h"
#include "fluid/fluid_params.h"
#include "fluid/grid.h"

namespace hf::fluid {

inline constexpr int kMaxPressureIterations = 100000;
// A float32 solve cannot go below about this relative residual.
inline constexpr float kMinPressureTolerance = 1e-7f;
inline constexpr float kMinFluidDensity = 1e-3f;  // kg/m^3
inline constexpr float kMaxFluidDensity = 1e5f;   // kg/m^3 (mercury is 1.35e4)
inline constexpr float kMaxGravity = 1e3f;        // m/s^2, also for buoyancy coefficients
inline constexpr float kMaxFactor = 1e3f;         // confinement, dissipation rates, concentration
inline constexpr float kMaxTemperature = 1e4f;    // K above ambient
inline constexpr float kMinCellSize = 1e-5f;      // m
inline constexpr float kMaxCellSize = 1e3f;       // m
inline constexpr float kMaxOriginOffset = 1e6f;   // m from the world origin
inline constexpr float kMinTimeStep = 1e-6f;      // s
inline constexpr float kMaxTimeStep = 10.0f;      // s
inline constexpr float kMaxProbeSpeed = 1e3f;     // m/s (incompressible flow is long gone by then)
inline constexpr float kMaxProbeSpin = 1e4f;      // rad/s

// The range of each FluidParams setting that has one: validate() checks these, and the bindings
// report them (FluidSettings.limits()) for the add-on's fields and the bake's checks.
inline constexpr Range kFluidDensityRange{kMinFluidDensity, kMaxFluidDensity};  // kg/m^3
inline constexpr Range kVorticityRange{0.0, kMaxFactor};                       // dimensionless
inline constexpr Range kSmokeWeightRange{-kMaxGravity, kMaxGravity};           // m/s^2 per concentration
inline constexpr Range kHeatBuoyancyRange{-kMaxGravity, kMaxGravity};          // m/s^2/K
inline constexpr Range kDissipationRange{0.0, kMaxFactor};                     // 1/s, smoke and heat
inline constexpr Range kPressureIterationsRange{1.0, kMaxPressureIterations};
// 0 runs a fixed count; otherwise at least kMinPressureTolerance (and the grid's floor,
// grid_checks.h) and below 1.
inline constexpr Range kPressureToleranceRange{0.0, 1.0, true};

void validate(const FluidParams& params);
void validate(const SmokeSource& source, const Grid& grid);
// A source's values, shared by the sphere and the mesh source: density 0..kMaxFactor,
// temperature 0..kMaxTemperature (K, or per second with SourceEmission::Rate).
void validateSourceValues(float density, float temperature_k, SourceEmission emission);

}  // namespace hf::fluid
