// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Solver settings, SI units. Changing them between steps is allowed.
#include <glm/glm.hpp>

namespace hf::fluid {

enum class Advection { SemiLagrangian, MacCormack };
enum class PressureSolverKind { Jacobi, Multigrid };

struct FluidParams {
  float density_kg_m3 = 1.2f;                  // rho of the fluid (air 1.2, water 1000)
  glm::vec3 gravity_m_s2{0.0f, 0.0f, -9.81f};  // its hydrostatic pressure acts on the probe
  bool open_top = false;                       // +z wall open to 0 Pa, else all walls closed
  Advection advection = Advection::SemiLagrangian;
  float vorticity_confinement = 0.0f;          // epsilon (dimensionless), 0 = off
  float smoke_weight_m_s2 = 0.0f;              // downward acceleration per unit smoke concentration
  float heat_buoyancy_m_s2_k = 0.0f;           // upward acceleration per kelvin above ambient
  float density_dissipation_1_s = 0.0f;        // smoke fades as exp(-rate t)
  float temperature_dissipation_1_s = 0.0f;    // heat fades as exp(-rate t)
  // Advection keeps the totals of smoke and heat (fluid/scalar_conservation.h); off: the raw
  // semi-Lagrangian / MacCormack result, which loses some.
  bool conserve_smoke = true;
  PressureSolverKind pressure_solver = PressureSolverKind::Jacobi;
  // Jacobi: sweeps per step; multigrid: CG iterations (one V-cycle each). With a tolerance,
  // the most the solve may run.
  int pressure_iterations = 40;
  // Relative residual ||rhs - A p|| / ||rhs|| (dimensionless) at which the solve stops; 0 runs
  // exactly pressure_iterations.
  float pressure_tolerance = 0.0f;
  bool compute_residual = true;                // measure the pressure solve's relative residual
  // Cut cells for the probe (sphere or mesh): its faces' open fractions from its geometry (Batty
  // et al. 2007), so the force changes continuously as it moves; off: faces covered by its voxels.
  bool cut_cells = true;
};

// How a smoke source (sphere or mesh, emitter/mesh_source.h) changes the cells it covers, with
// c its coverage of the cell (0..1; a sphere covers a cell whose centre it holds, c = 1):
//   Hold: smoke and heat are raised to at least c x the source's values (density: a
//         concentration, temperature: K above ambient);
//   Rate: c x the values are added per second (density: concentration per second,
//         temperature: K per second), so a source of volume V adds density x V x dt each step.
enum class SourceEmission { Hold, Rate };

// Smoke emitter: a sphere that emits smoke and heat in the cells whose centre it holds.
struct SmokeSource {
  bool enabled = false;
  glm::vec3 centre_m{0.0f};   // world position, m
  float radius_m = 0.0f;      // m
  float density = 1.0f;       // smoke concentration (Hold), per second (Rate)
  float temperature_k = 0.0f; // K above ambient (Hold), K/s (Rate)
  SourceEmission emission = SourceEmission::Hold;
};

}  // namespace hf::fluid
