// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// fitSlope: the least-squares slope of y against x over n samples, the fit behind both local drag
// models (drag_predictor.h: B of the prediction F0 + B (v - v0); fluid_model.h: B of the local
// model, with the added-mass reaction taken out of y first):
//   slope = sum (x_i - mean x) (y_i - mean y) / sum (x_i - mean x)^2      (in double)
// None where the x values hardly differ, sum (x_i - mean x)^2 <= n min_spread^2 (an rms spread of
// at most min_spread, in x's unit): the samples then say nothing about the slope. The slope may be
// non-finite when a sample is; the caller decides what to keep.
#include <optional>

namespace hf::haptics {

std::optional<double> fitSlope(const double* x, const double* y, int n, double min_spread);

}  // namespace hf::haptics
