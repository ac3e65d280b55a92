// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The seed's force smoother (Yang et al. 2008, after Baxter and Lin 2004): a discrete first-order
// low-pass run at the haptic rate on the force the GPU delivers at its own, lower frame rate.
// Its bandwidth follows the measured simulation rate: cutoff = bandwidth_ratio * rate, so a slow
// frame rate gets more smoothing of its staircase and a fast one less delay.
//
// Discretisation: y += a (x - y) with a = 1 - exp(-2 pi fc dt), the exact sampled response of
// tau dy/dt = x - y (tau = 1 / (2 pi fc)) to a held input, so any dt gives the analytic step
// response y(t) = 1 - exp(-t / tau) at the samples.
#include <glm/glm.hpp>

namespace hf::haptics {

struct LowPassSettings {
  bool enabled = true;
  double bandwidth_ratio = 0.5;   // cutoff / simulation rate (dimensionless), > 0
  double min_cutoff_hz = 1.0;     // cutoff range, Hz
  double max_cutoff_hz = 200.0;
  void validate() const;          // throws InvalidArgument naming the bad value
};

// Cutoff (Hz) for a measured simulation rate (Hz); a rate <= 0 (unknown) gives min_cutoff_hz.
double cutoffForRate(const LowPassSettings& s, double sim_rate_hz);

class LowPassFilter {
 public:
  // One sample: input x, period dt_s (> 0), cutoff (Hz). Returns the new output.
  glm::vec3 update(const glm::vec3& x, double dt_s, double cutoff_hz);
  void reset(const glm::vec3& value = glm::vec3(0.0f)) { y_ = value; }
  const glm::vec3& value() const { return y_; }

 private:
  glm::vec3 y_{0.0f};
};

}  // namespace hf::haptics
