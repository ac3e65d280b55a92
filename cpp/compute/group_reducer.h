// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The second level of every parallel reduction: a first-level stage writes one vec4 per
// workgroup into partials(); reduce() sums `count` of them on the GPU into a result slot, and
// readResults() fetches all slots in one small read-back.
#include <cstddef>
#include <glm/glm.hpp>
#include <memory>
#include <vector>

#include "compute/compute_program.h"
#include "compute/storage_buffer.h"

namespace hf::compute {

class GroupReducer {
 public:
  // `max_groups`: the most first-level workgroups any stage dispatches; `slots`: result vec4s.
  GroupReducer(std::size_t max_groups, std::size_t slots);

  std::size_t maxGroups() const { return max_groups_; }
  void bindPartials(unsigned binding) const { partials_.bind(binding); }
  StorageBuffer& partials() { return partials_; }  // max_groups vec4s
  void bindResults(unsigned binding) const { results_.bind(binding); }  // for GPU-side use of a sum
  void clearResults() { results_.clear(); }
  // Sums partials[first .. first + count) into result slot `slot`.
  void reduce(std::size_t count, std::size_t slot, std::size_t first = 0);
  std::vector<glm::vec4> readResults() const;

 private:
  std::size_t max_groups_;
  std::size_t slots_;
  StorageBuffer partials_;
  StorageBuffer results_;
  ComputeProgram program_;
};

}  // namespace hf::compute
