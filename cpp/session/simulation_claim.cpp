// SPDX-License-Identifier: GPL-3.0-or-later
#include "session/simulation_claim.h"

#include <mutex>
#include <unordered_set>

#include "common/error.h"

namespace hf::session {

namespace {

struct Registry {
  std::mutex mutex;
  std::unordered_set<const Simulation*> held;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: sessions may end during static teardown
  return *r;
}

}  // namespace

SimulationClaim::SimulationClaim(const Simulation& sim, const std::string& action) : sim_(&sim) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  if (!r.held.insert(sim_).second) {
    throw Error("this Simulation is in use (another running HapticSession drives it): cannot " + action +
                "; stop that session first (two sessions would both move the probe every step), or give this "
                "one its own Simulation");
  }
}

SimulationClaim::~SimulationClaim() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  r.held.erase(sim_);
}

bool SimulationClaim::claimed(const Simulation& sim) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return r.held.count(&sim) > 0;
}

}  // namespace hf::session
