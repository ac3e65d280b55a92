// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/group_reducer.h"

#include "common/error.h"

namespace hf::compute {
namespace {
constexpr int kReduceSize = 256;  // invocations of the single reduce workgroup
}

GroupReducer::GroupReducer(std::size_t max_groups, std::size_t slots)
    : max_groups_(max_groups),
      slots_(slots),
      partials_(max_groups * sizeof(glm::vec4), "reduction partials"),
      results_(slots * sizeof(glm::vec4), "reduction results"),
      program_("reduce.comp", {{"REDUCE_SIZE", std::to_string(kReduceSize)}}) {
  results_.clear();
}

void GroupReducer::reduce(std::size_t count, std::size_t slot, std::size_t first) {
  if (first > max_groups_ || count > max_groups_ - first || slot >= slots_) {
    throw Error("reduce: count, first or slot out of range");
  }
  partials_.bind(0);
  results_.bind(1);
  program_.set("u_count", static_cast<unsigned>(count));
  program_.set("u_slot", static_cast<unsigned>(slot));
  program_.set("u_first", static_cast<unsigned>(first));
  program_.dispatch(glm::ivec3(kReduceSize, 1, 1));
}

std::vector<glm::vec4> GroupReducer::readResults() const {
  std::vector<glm::vec4> out(slots_);
  results_.download(out.data(), out.size() * sizeof(glm::vec4));
  return out;
}

}  // namespace hf::compute
