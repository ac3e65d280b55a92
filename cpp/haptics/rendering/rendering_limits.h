// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The force gain a device can render for a fluid probe: the default of HapticSession.
//
// Seen from the device, the fluid acts on the probe mostly as its added mass m_a: a device
// velocity v moves the probe at scale * v, so per unit force gain the device renders a mass
//   M = |scale| * m_a                               (kg; scale: domain m per device m)
// A simulation that updates the force once per step T turns a velocity change within a step
// into the force M dv / T and a displacement dx into M dx / T^2: per unit gain it renders a
//   damping   B = M / T    (N s/m)      and a stiffness   K = M / T^2   (N/m).
// The device stays stable up to its maximum damping and stiffness (DeviceInfo), so
//   gain = min(1, max_damping * T / M, max_stiffness * T^2 / M).
// A device that reports neither limit (virtual devices) gets gain 1.
#include <string>

#include "haptics/devices/device.h"

namespace hf::haptics {

struct GainChoice {
  float gain = 1.0f;          // device N per fluid N
  double mass_kg = 0.0;       // M per unit gain, kg
  double damping_n_s_m = 0.0; // B per unit gain, N s/m
  double stiffness_n_m = 0.0; // K per unit gain, N/m
  std::string reason;         // one line: what bounded the gain, with the numbers
};

// added_mass_kg: the probe's added mass in the fluid (> 0); scale: domain m per device m (the
// largest |scale| over the axes); step_s: the shortest simulation step the session takes (> 0).
// Throws InvalidArgument for a non-finite or non-positive input.
GainChoice renderableForceGain(const DeviceInfo& device, double added_mass_kg, double scale, double step_s);

// With the virtual coupling (virtual_coupling.h) the added mass and the drag are rendered at the
// haptic rate by the proxy, which stays passive at any gain. What still reaches the hand once per
// simulation step is the local model's steady part (fluid_model.h), and with it whatever of the
// fluid's reaction to the probe's motion the model did not take out: kHeldShare of the added
// mass. Measured: a sphere of r = 0.1 m accelerated through water, the engine's reaction is 0.92
// (32^3) and 0.80 (20^3) of the model's rho V / 2; kHeldShare = 0.1 with kGainMargin = 0.5 covers
// both. On the simulated Falcon at the gain this gives (air, live demo's scene: 62; water, r 0.1 m,
// scale 6: 0.080): quick strokes at 32^3 delivered 0.13-0.68 mJ to the hand, a resting hand at
// 20^3 in water 0-1.04 mJ in 5 s. Held for a step T, that share renders kHeldShare M / T and
// kHeldShare M / T^2 per unit gain, and the gain keeps both at kGainMargin of the device's limits:
//   gain = kGainMargin min(max_damping T / (kHeldShare M), max_stiffness T^2 / (kHeldShare M))
// with no cap at 1 (a weak fluid may be amplified), and a steady force (buoyancy) at rest of at
// most kSteadyShareOfMaxForce of max_force, so the hand keeps room to feel the flow beside it.
// The step counts at most this long (s): by the M / T form a slower simulation would allow a larger
// gain, but the residual it holds does not leak less (strokes on the simulated Falcon with the
// simulation slowed to 3.7 Hz: 0.45-0.68 mJ at the gain of a 10 ms step; 5.8 mJ (air) and 34 mJ
// (water) at the 20 times larger gain of its 0.2 s step). Independent of the machine's speed.
inline constexpr double kGainStepCapS = 0.01;
inline constexpr double kHeldShare = 0.1;
inline constexpr double kGainMargin = 0.5;
inline constexpr double kSteadyShareOfMaxForce = 0.5;

// steady_force_n: the fluid's force on the probe at rest (>= 0, N: rho |g| V); max_force_n: the
// session's force bound (> 0). The other arguments as renderableForceGain's.
GainChoice coupledForceGain(const DeviceInfo& device, double added_mass_kg, double scale, double step_s,
                            double steady_force_n, double max_force_n);

// Added mass of a body of volume_m3 in a fluid of density_kg_m3: C_m rho V, C_m = 1/2 (a
// sphere in unbounded potential flow; the same coefficient is used for other shapes).
double addedMassKg(double density_kg_m3, double volume_m3);

}  // namespace hf::haptics
