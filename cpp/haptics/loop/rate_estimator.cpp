// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/loop/rate_estimator.h"

namespace hf::haptics {

void RateEstimator::add(double time_s) {
  if (last_s_ >= 0.0 && time_s > last_s_) {
    const double dt = time_s - last_s_;
    interval_s_ = interval_s_ > 0.0 ? interval_s_ + weight_ * (dt - interval_s_) : dt;
  }
  last_s_ = time_s;
}

}  // namespace hf::haptics
