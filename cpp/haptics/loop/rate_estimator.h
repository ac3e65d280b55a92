// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// RateEstimator: a smoothed event rate (Hz) from event times (s): an exponential average of
// the intervals, so one slow frame moves it a little and a lasting change moves it fully.
namespace hf::haptics {

class RateEstimator {
 public:
  explicit RateEstimator(double weight = 0.2) : weight_(weight) {}
  void add(double time_s);
  double rateHz() const { return interval_s_ > 0.0 ? 1.0 / interval_s_ : 0.0; }  // 0 until two events
  void reset() { last_s_ = -1.0; interval_s_ = 0.0; }

 private:
  double weight_;
  double last_s_ = -1.0;
  double interval_s_ = 0.0;
};

}  // namespace hf::haptics
