// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_coarsest.comp built as C++ (cpu/kernel.h), with a runner of its own: the shader
// solves the coarsest level in one workgroup with a barrier between half-sweeps, which C++ has
// no form of; the runner calls the shader's coarseCell / coarseUpdate for every cell of each
// half-sweep in turn instead. A half-sweep's cells read only the other colour, so the order
// within it does not change the result: the same arithmetic as the GPU's, to the bit.
#include "cpu/kernels/kernel_list.h"

#include <vector>

#include "common/error.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#define COARSEST 16  // the largest level this build takes (MultigridVCycle::kCoarsestCells is 4)
struct MgCoarsest : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_coarsest.comp"
  static constexpr int kMaxCells = COARSEST;
};
#undef COARSEST

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

class MgCoarsestRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3& local, const Bindings&, ThreadPool&) override {
    if (glm::any(glm::greaterThan(local, glm::ivec3(MgCoarsest::kMaxCells)))) {
      throw Error("mg_coarsest: a coarsest level of " + std::to_string(local.x) + " cells per axis is more than the CPU build's " +
                  std::to_string(MgCoarsest::kMaxCells));
    }
    MgCoarsest& k = kernel_;
    std::vector<glm::ivec3> cells;
    std::vector<MgCoarsest::CoarseCell> data;
    for (int z = 0; z < local.z; ++z) {
      for (int y = 0; y < local.y; ++y) {
        for (int x = 0; x < local.x; ++x) {
          const glm::ivec3 c(x, y, z);
          cells.push_back(c);
          data.push_back(k.coarseCell(c));
          k.s_x[k.slot(c)] = 0.0f;
        }
      }
    }
    for (int h = 0; h < 4 * k.u_pairs; ++h) {
      const int want = k.colourOfHalfSweep(h);
      for (std::size_t i = 0; i < cells.size(); ++i) {
        const glm::ivec3 c = cells[i];
        if (((c.x + c.y + c.z) & 1) == want && data[i].live) k.s_x[k.slot(c)] = k.coarseUpdate(c, data[i]);
      }
    }
    for (const glm::ivec3& c : cells) {
      if (k.inGrid(c)) glsl::imageStore(k.u_x, c, glm::vec4(k.s_x[k.slot(c)]));
    }
  }

 private:
  KernelSlots slots_;
  MgCoarsest kernel_{&slots_};
};

}  // namespace

void addMgCoarsest(KernelRegistry& r) { r.add<MgCoarsestRunner>("mg_coarsest.comp", {}); }

}  // namespace hf::cpu::kernels
