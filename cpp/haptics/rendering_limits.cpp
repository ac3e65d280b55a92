#include "haptics/rendering_limits.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/format.h"

namespace hf::haptics {

namespace {
constexpr double kAddedMassCoefficient = 0.5;  // sphere, potential flow
}  // namespace

double addedMassKg(double density_kg_m3, double volume_m3) { return kAddedMassCoefficient * density_kg_m3 * volume_m3; }

GainChoice renderableForceGain(const DeviceInfo& device, double added_mass_kg, double scale, double step_s) {
  if (!std::isfinite(added_mass_kg) || added_mass_kg <= 0.0) {
    throw InvalidArgument("force gain: the probe's added mass must be a positive number of kg, got " + num(added_mass_kg));
  }
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InvalidArgument("force gain: the workspace scale must be a positive number, got " + num(scale));
  }
  if (!std::isfinite(step_s) || step_s <= 0.0) {
    throw InvalidArgument("force gain: the simulation step must be a positive number of seconds, got " + num(step_s));
  }
  GainChoice c;
  c.mass_kg = scale * added_mass_kg;
  c.damping_n_s_m = c.mass_kg / step_s;
  c.stiffness_n_m = c.mass_kg / (step_s * step_s);
  const double by_damping = device.max_damping_n_s_m > 0.0f ? device.max_damping_n_s_m / c.damping_n_s_m : 1.0;
  const double by_stiffness = device.max_stiffness_n_m > 0.0f ? device.max_stiffness_n_m / c.stiffness_n_m : 1.0;
  const double gain = std::min({1.0, by_damping, by_stiffness});
  c.gain = static_cast<float>(gain);
  const std::string fluid = "the fluid renders " + num3(c.mass_kg) + " kg, " + num3(c.damping_n_s_m) + " N s/m and " +
                            num3(c.stiffness_n_m) + " N/m per unit gain (added mass " + num3(added_mass_kg) + " kg x scale " +
                            num3(scale) + ", step " + num3(step_s) + " s)";
  if (device.max_damping_n_s_m <= 0.0f && device.max_stiffness_n_m <= 0.0f) {
    c.reason = "force gain 1: '" + device.name + "' reports no rendering limits";
  } else if (gain >= 1.0) {
    c.reason = "force gain 1: " + fluid + ", within the limits of '" + device.name + "'";
  } else if (by_damping <= by_stiffness) {
    c.reason = "force gain " + num3(gain) + " = max damping " + num3(device.max_damping_n_s_m) + " N s/m of '" +
               device.name + "' / " + num3(c.damping_n_s_m) + " N s/m: " + fluid;
  } else {
    c.reason = "force gain " + num3(gain) + " = max stiffness " + num3(device.max_stiffness_n_m) + " N/m of '" +
               device.name + "' / " + num3(c.stiffness_n_m) + " N/m: " + fluid;
  }
  return c;
}

}  // namespace hf::haptics
