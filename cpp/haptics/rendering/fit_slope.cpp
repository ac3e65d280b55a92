// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/fit_slope.h"

namespace hf::haptics {

std::optional<double> fitSlope(const double* x, const double* y, int n, double min_spread) {
  double mx = 0.0, my = 0.0;
  for (int i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0.0, sxy = 0.0;
  for (int i = 0; i < n; ++i) {
    const double dx = x[i] - mx;
    sxx += dx * dx;
    sxy += dx * (y[i] - my);
  }
  if (!(sxx > n * min_spread * min_spread)) return std::nullopt;
  return sxy / sxx;
}

}  // namespace hf::haptics
