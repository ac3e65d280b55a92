// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/reduce.comp built as C++ (cpu/kernel.h), with a runner of its own: the shader's tree
// over one workgroup needs barriers, which C++ has no form of. The runner takes each lane's share
// with the shader's laneSum and adds the lanes in the tree's order, so the sum is the GPU's to
// the bit for the same partials.
#include "cpu/kernels/kernel_list.h"

#include "common/error.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#define REDUCE_SIZE 256  // the largest workgroup this build takes (GroupReducer's is 256)
struct Reduce : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "reduce.comp"
  static constexpr uint kMaxLanes = REDUCE_SIZE;
};
#undef REDUCE_SIZE

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

class ReduceRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3& local, const Bindings&, ThreadPool&) override {
    const unsigned lanes = static_cast<unsigned>(local.x);
    if (lanes > Reduce::kMaxLanes || (lanes & (lanes - 1)) != 0) {
      throw Error("reduce: a workgroup of " + std::to_string(lanes) + " lanes is not a power of two up to " +
                  std::to_string(Reduce::kMaxLanes));
    }
    Reduce& k = kernel_;
    if (k.u_first + k.u_count > k.partials.length() || k.u_slot >= k.results.length()) {
      throw Error("reduce: the range or the slot is past its buffer");
    }
    for (unsigned i = 0; i < lanes; ++i) k.s_sum[i] = k.laneSum(i);
    for (unsigned stride = lanes / 2; stride > 0; stride >>= 1) {
      for (unsigned i = 0; i < stride; ++i) k.s_sum[i] += k.s_sum[i + stride];
    }
    k.results[k.u_slot] = k.s_sum[0];
  }

 private:
  KernelSlots slots_;
  Reduce kernel_{&slots_};
};

}  // namespace

void addReduce(KernelRegistry& r) { r.add<ReduceRunner>("reduce.comp", {}); }

}  // namespace hf::cpu::kernels
