// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/rendering_limits.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"
#include "common/format.h"

namespace hf::haptics {

namespace {
constexpr double kAddedMassCoefficient = 0.5;  // sphere, potential flow
}  // namespace

double addedMassKg(double density_kg_m3, double volume_m3) { return kAddedMassCoefficient * density_kg_m3 * volume_m3; }

namespace {
void checkInputs(double added_mass_kg, double scale, double step_s) {
  if (!std::isfinite(added_mass_kg) || added_mass_kg <= 0.0) {
    throw InvalidArgument("force gain: the probe's added mass must be a positive number of kg, got " + num(added_mass_kg));
  }
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InvalidArgument("force gain: the workspace scale must be a positive number, got " + num(scale));
  }
  if (!std::isfinite(step_s) || step_s <= 0.0) {
    throw InvalidArgument("force gain: the simulation step must be a positive number of seconds, got " + num(step_s));
  }
}
}  // namespace

GainChoice renderableForceGain(const DeviceInfo& device, double added_mass_kg, double scale, double step_s) {
  checkInputs(added_mass_kg, scale, step_s);
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

namespace hf::haptics {

GainChoice coupledForceGain(const DeviceInfo& device, double added_mass_kg, double scale, double step_s,
                            double steady_force_n, double max_force_n) {
  checkInputs(added_mass_kg, scale, step_s);
  if (!std::isfinite(steady_force_n) || steady_force_n < 0.0) {
    throw InvalidArgument("force gain: the steady force must be a finite number of N >= 0, got " + num(steady_force_n));
  }
  if (!std::isfinite(max_force_n) || max_force_n <= 0.0) {
    throw InvalidArgument("force gain: max_force must be a positive number of N, got " + num(max_force_n));
  }
  step_s = std::min(step_s, kGainStepCapS);
  GainChoice c;
  c.mass_kg = scale * added_mass_kg;
  const double held_kg = kHeldShare * c.mass_kg;
  c.damping_n_s_m = held_kg / step_s;
  c.stiffness_n_m = held_kg / (step_s * step_s);
  if (device.max_damping_n_s_m <= 0.0f && device.max_stiffness_n_m <= 0.0f) {
    c.gain = 1.0f;
    c.reason = "force gain 1: '" + device.name + "' reports no rendering limits";
    return c;
  }
  const double inf = std::numeric_limits<double>::infinity();
  const double by_damping = device.max_damping_n_s_m > 0.0f ? kGainMargin * device.max_damping_n_s_m / c.damping_n_s_m : inf;
  const double by_stiffness = device.max_stiffness_n_m > 0.0f ? kGainMargin * device.max_stiffness_n_m / c.stiffness_n_m : inf;
  const double by_steady = steady_force_n > 0.0 ? kSteadyShareOfMaxForce * max_force_n / steady_force_n : inf;
  const double gain = std::min({by_damping, by_stiffness, by_steady});
  c.gain = static_cast<float>(gain);
  const std::string held = "the local model renders the added mass " + num3(c.mass_kg) + " kg per unit gain at 1 kHz (" +
                           num3(added_mass_kg) + " kg x scale " + num3(scale) + "); held per step " + num3(step_s) +
                           " s: its residual " + num3(kHeldShare) + " x that, " + num3(c.damping_n_s_m) + " N s/m and " +
                           num3(c.stiffness_n_m) + " N/m per unit gain";
  if (by_steady <= by_damping && by_steady <= by_stiffness) {
    c.reason = "force gain " + num3(gain) + ": the steady force at rest " + num3(steady_force_n) + " N x gain = " +
               num3(kSteadyShareOfMaxForce) + " x max_force " + num3(max_force_n) + " N (" + held + ")";
  } else if (by_damping <= by_stiffness) {
    c.reason = "force gain " + num3(gain) + " = margin " + num3(kGainMargin) + " x max damping " +
               num3(device.max_damping_n_s_m) + " N s/m of '" + device.name + "' / " + num3(c.damping_n_s_m) +
               " N s/m: " + held;
  } else {
    c.reason = "force gain " + num3(gain) + " = margin " + num3(kGainMargin) + " x max stiffness " +
               num3(device.max_stiffness_n_m) + " N/m of '" + device.name + "' / " + num3(c.stiffness_n_m) + " N/m: " + held;
  }
  return c;
}

}  // namespace hf::haptics
