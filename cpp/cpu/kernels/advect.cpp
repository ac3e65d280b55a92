// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/advect.comp built as C++ (cpu/kernel.h).
// Every access is in range by the shader's own construction (its lookups are clamped to the
// field), so it runs unchecked, with a row loop of its own: advection is the largest stage of a
// CPU step. The loop calls the shader's advectedValues (branch-free: the back-trace, the
// lookups, the decay and the solid's zero) for every texel of a row and stores the row.
#include "cpu/kernels/kernel_list.h"

#include "common/error.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

#define FIELD_AT 0
struct AdvectUUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 1
struct AdvectVUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 2
struct AdvectWUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
struct AdvectScalarUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
#define PAIR 1
struct AdvectPairUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT
#undef PAIR

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

template <class K, bool kPair>
class AdvectRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 size = glm::min(n, kernel_.u_field_size);
    if (kernel_.u_dst.size != kernel_.u_field_size) throw Error("advect: the output is not bound at the field's size");
    forRows(
        size, pool,
        [&](int y, int z) { runBest(bindings.x86_v3, [&] { row(y, z, size.x); }); },
        [](int, int) {});
  }

 private:
  __attribute__((always_inline)) void row(int y, int z, int width) const {
    K k(kernel_);
    float* __restrict out = static_cast<float*>(k.u_dst.data) + k.u_dst.index(glm::ivec3(0, y, z));
    float* __restrict out2 = nullptr;
    if constexpr (kPair) out2 = static_cast<float*>(k.u_dst2.data) + k.u_dst2.index(glm::ivec3(0, y, z));
#pragma omp simd
    for (int x = 0; x < width; ++x) {
      const glm::vec2 v = k.advectedValues(glm::ivec3(x, y, z));
      out[x] = v.x;
      if constexpr (kPair) out2[x] = v.y;
    }
  }

  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace

void addAdvect(KernelRegistry& r) {
  r.add<AdvectRows<AdvectUUnchecked, false>>("advect.comp", {{"FIELD_AT", "0"}});
  r.add<AdvectRows<AdvectVUnchecked, false>>("advect.comp", {{"FIELD_AT", "1"}});
  r.add<AdvectRows<AdvectWUnchecked, false>>("advect.comp", {{"FIELD_AT", "2"}});
  r.add<AdvectRows<AdvectScalarUnchecked, false>>("advect.comp", {{"FIELD_AT", "3"}});
  r.add<AdvectRows<AdvectPairUnchecked, true>>("advect.comp", {{"FIELD_AT", "3"}, {"PAIR", "1"}});
}

}  // namespace hf::cpu::kernels
