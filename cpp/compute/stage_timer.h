// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Device time per named stage (GPU: timestamp queries read after the step's own read-back, so
// they add no stall; CPU: the wall time of the stage's dispatches).
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "compute/device.h"

namespace hf::compute {

class StageTimer {
 public:
  StageTimer() : impl_(currentDevice().makeTimer()) {}

  void begin() { impl_->begin(); }                               // starts a new step's record
  void mark(const std::string& stage) { impl_->mark(stage); }   // the time since the previous mark goes to `stage`
  // Milliseconds per stage (stages marked more than once are summed), in first-mark order.
  std::vector<std::pair<std::string, double>> collect() { return impl_->collect(); }

 private:
  std::unique_ptr<TimerImpl> impl_;
};

}  // namespace hf::compute
