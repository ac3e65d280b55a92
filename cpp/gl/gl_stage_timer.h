// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// compute::StageTimer on GL: GPU time per named stage from timestamp queries (RAII query pool).
// Queries are only recorded during a step and read after the step's own read-back, so they add
// no stall.
#include <string>
#include <utility>
#include <vector>

#include "compute/device.h"

namespace hf::gl {

class GlStageTimer final : public compute::TimerImpl {
 public:
  GlStageTimer() = default;
  ~GlStageTimer() override;
  GlStageTimer(const GlStageTimer&) = delete;
  GlStageTimer& operator=(const GlStageTimer&) = delete;

  void begin() override;
  void mark(const std::string& stage) override;
  std::vector<std::pair<std::string, double>> collect() override;

 private:
  unsigned int query(std::size_t i);

  std::vector<unsigned int> pool_;
  std::vector<std::string> stages_;  // stages_[i] ends at query i+1
  std::size_t used_ = 0;
};

}  // namespace hf::gl
