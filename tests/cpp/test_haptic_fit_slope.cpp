// SPDX-License-Identifier: GPL-3.0-or-later
// fitSlope, the least-squares slope behind the drag predictor's and the local model's drag.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "haptics/rendering/fit_slope.h"

namespace hf::haptics {
namespace {

TEST(HapticFitSlope, GivesTheSlopeOfALineWhateverItsIntercept) {
  const double x[] = {-0.2, 0.1, 0.3, 0.05};
  double y[4];
  for (int i = 0; i < 4; ++i) y[i] = 7.0 - 2.5 * x[i];
  const std::optional<double> b = fitSlope(x, y, 4, 1e-3);
  ASSERT_TRUE(b);
  EXPECT_NEAR(*b, -2.5, 1e-12);
}

TEST(HapticFitSlope, GivesTheLeastSquaresSlopeOfScatteredSamples) {
  // x = -1, 0, 1; y = 0, 0, 3: slope sum dx dy / sum dx^2 = (-1 * -1 + 1 * 2) / 2 = 1.5.
  const double x[] = {-1.0, 0.0, 1.0}, y[] = {0.0, 0.0, 3.0};
  const std::optional<double> b = fitSlope(x, y, 3, 0.1);
  ASSERT_TRUE(b);
  EXPECT_DOUBLE_EQ(*b, 1.5);
}

TEST(HapticFitSlope, SaysNothingWhereTheXValuesHardlyDiffer) {
  // rms spread of x about its mean: 0.001 x sqrt(2/3) = 0.00082.
  const double x[] = {0.2, 0.201, 0.199}, y[] = {1.0, 2.0, 0.0};
  EXPECT_FALSE(fitSlope(x, y, 3, 0.001));
  EXPECT_TRUE(fitSlope(x, y, 3, 0.0008));
  const double same[] = {0.5, 0.5, 0.5};
  EXPECT_FALSE(fitSlope(same, y, 3, 0.0));  // no spread at all: not even with no threshold
}

}  // namespace
}  // namespace hf::haptics
