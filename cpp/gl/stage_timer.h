// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// GPU time per named stage from GL timestamp queries (RAII query pool). Queries are only
// recorded during a step and read after the step's own read-back, so they add no stall.
#include <string>
#include <utility>
#include <vector>

namespace hf::gl {

class StageTimer {
 public:
  StageTimer();
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

  void begin();                          // starts a new step's record
  void mark(const std::string& stage);   // the GPU time since the previous mark goes to `stage`
  // Milliseconds per stage (stages marked more than once are summed), in first-mark order.
  std::vector<std::pair<std::string, double>> collect();

 private:
  unsigned int query(std::size_t i);

  std::vector<unsigned int> pool_;
  std::vector<std::string> stages_;  // stages_[i] ends at query i+1
  std::size_t used_ = 0;
};

}  // namespace hf::gl
