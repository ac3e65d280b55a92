// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// SimulationClaim: exclusive driving of a Simulation by one HapticSession. Two sessions on one
// simulation would both move its probe every step (it jumps between their poses) and both read
// its force; the claim turns the second start() into a clear error instead. Keyed by the
// Simulation's address (a session's simulation outlives it), in a process-wide registry;
// Simulation itself is unchanged. Host calls on the simulation (step(), set_probe()) are not
// claimed.
#include <string>

namespace hf::session {

class Simulation;

class SimulationClaim {
 public:
  // Throws hf::Error saying what to do if another claim holds `sim`; `action` is what the
  // caller was about to do ("start a haptic session on it").
  SimulationClaim(const Simulation& sim, const std::string& action);
  ~SimulationClaim();
  SimulationClaim(const SimulationClaim&) = delete;
  SimulationClaim& operator=(const SimulationClaim&) = delete;

  static bool claimed(const Simulation& sim);

 private:
  const Simulation* sim_;
};

}  // namespace hf::session
