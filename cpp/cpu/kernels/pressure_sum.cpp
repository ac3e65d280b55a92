// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pressure_sum.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage: one
// invocation per row of cells, run by pressure_row.h's CellRowRunner). The shader's sumTerms gives
// every cell's terms (the value and the fluid count), vectorized over the row (a cell reads only itself), summed by
// parts (rowPartsOf, common.glsl's ROW_PARTS) as the shader sums them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PressureSumUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pressure_sum.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PressureSumUnchecked;

struct SumRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pressure_sum";
    checkBound(kernel.u_pressure, res, stage, "field");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res) {
    const int n = res.x;
    const int at = rowStart(res, y, z);
    const std::uint8_t* __restrict m = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    float* __restrict t = termRows<2>(n);
    const float* __restrict v = static_cast<const float*>(k.u_pressure.data) + at;
#pragma omp simd
    for (int i = 0; i < n; ++i) {
      const glm::vec4 w = k.sumTerms(m[i], v[i]);
      t[i] = w.x;
      t[n + i] = w.y;
    }
    k.partials[static_cast<std::size_t>(y + res.y * z)] = rowPartsOf<2>(k, t, n);
  }
};

}  // namespace

void addPressureSum(KernelRegistry& r) { r.add<CellRowRunner<K, SumRows>>("pressure_sum.comp", {}); }

}  // namespace hf::cpu::kernels
