// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/fluid_model.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/format.h"
#include "haptics/rendering/fit_slope.h"

namespace hf::haptics {

FluidModel::FluidModel(double added_mass_kg, double max_drag_n_s_m)
    : added_mass_kg_(added_mass_kg), max_drag_n_s_m_(max_drag_n_s_m), mass_kg_(added_mass_kg) {
  if (!std::isfinite(added_mass_kg) || added_mass_kg < 0.0) {
    throw InvalidArgument("fluid model: the probe's added mass must be a finite number of kg >= 0, got " + num(added_mass_kg));
  }
  if (!(max_drag_n_s_m > 0.0)) {
    throw InvalidArgument("fluid model: the largest drag must be a positive number of N s/m, got " + num(max_drag_n_s_m));
  }
}

void FluidModel::addFrame(const glm::vec3& force_n, const glm::vec3& velocity_m_s, double step_s) {
  accel_m_s2_ = (frames_ > 0 && step_s > 0.0 && std::isfinite(step_s))
                    ? (velocity_m_s - last_velocity_m_s_) / static_cast<float>(step_s)
                    : glm::vec3(0.0f);
  last_velocity_m_s_ = velocity_m_s;
  ++frames_;
  const int newest = next_;
  forces_[next_] = force_n;
  velocities_[next_] = velocity_m_s;
  accels_[next_] = accel_m_s2_;
  next_ = (next_ + 1) % kWindow;
  if (held_ < kWindow) ++held_;
  fitMass();
  fitDrag();
  // The force with the added-mass reaction taken out (what drag and the steady part make), less the drag.
  steady_n_ = force_n + static_cast<float>(mass_kg_) * accel_m_s2_ - drag_n_s_m_ * velocities_[newest];
}

void FluidModel::fitMass() {
  if (held_ < 4 || !(added_mass_kg_ > 0.0)) return;
  // Per axis: F = c + B v - m a over the window. With the mean and the velocity partialled out
  // (residuals of a and F after their regression on v), m is the slope of F against -a; the
  // axes share m (pooled numerator and denominator).
  double num = 0.0, den = 0.0;
  for (int ax = 0; ax < 3; ++ax) {
    double mv = 0.0, ma = 0.0, mf = 0.0;
    for (int i = 0; i < held_; ++i) {
      mv += velocities_[i][ax];
      ma += accels_[i][ax];
      mf += forces_[i][ax];
    }
    mv /= held_;
    ma /= held_;
    mf /= held_;
    double svv = 0.0, sva = 0.0, svf = 0.0, saa = 0.0, saf = 0.0;
    for (int i = 0; i < held_; ++i) {
      const double v = velocities_[i][ax] - mv, a = accels_[i][ax] - ma, f = forces_[i][ax] - mf;
      svv += v * v;
      sva += v * a;
      svf += v * f;
      saa += a * a;
      saf += a * f;
    }
    if (svv > 0.0) {  // partial out the velocity
      saa -= sva * sva / svv;
      saf -= sva * svf / svv;
    }
    num -= saf;
    den += saa;
  }
  if (!(den > held_ * kMinAccelSpread * kMinAccelSpread) || !std::isfinite(num)) return;  // keep the last m_a
  mass_kg_ = std::clamp(num / den, kMinMassShare * added_mass_kg_, kMaxMassShare * added_mass_kg_);
}

void FluidModel::fitDrag() {
  if (held_ < 3) return;
  constexpr double kMinVelocitySpread = 1e-3;  // m/s rms: below, the window says nothing about B
  std::array<double, kWindow> v{}, f{};
  for (int a = 0; a < 3; ++a) {
    for (int i = 0; i < held_; ++i) {
      v[i] = velocities_[i][a];
      f[i] = forces_[i][a] + mass_kg_ * accels_[i][a];  // the added-mass reaction taken out
    }
    const std::optional<double> b = fitSlope(v.data(), f.data(), held_, kMinVelocitySpread);
    if (!b) continue;  // keep the last slope
    drag_n_s_m_[a] = std::isfinite(*b) ? static_cast<float>(std::clamp(*b, -max_drag_n_s_m_, 0.0)) : 0.0f;
  }
}

void FluidModel::reset() {
  held_ = next_ = 0;
  steady_n_ = drag_n_s_m_ = accel_m_s2_ = last_velocity_m_s_ = glm::vec3(0.0f);
  mass_kg_ = added_mass_kg_;
  frames_ = 0;
}

}  // namespace hf::haptics
