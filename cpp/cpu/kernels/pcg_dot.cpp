// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_dot.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage: one
// invocation per row of cells, run by pressure_row.h's CellRowRunner). The shader's dotTerm gives
// every cell's term of a.b, vectorized over the row (a cell reads only itself), summed by
// parts (rowPartsOf, common.glsl's ROW_PARTS) as the shader sums them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgDotUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_dot.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PcgDotUnchecked;

struct DotRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_dot";
    checkBound(kernel.u_a, res, stage, "a");
    checkBound(kernel.u_b, res, stage, "b");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res) {
    const int n = res.x;
    const int at = rowStart(res, y, z);
    const std::uint8_t* __restrict m = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    float* __restrict t = termRows<1>(n);
    const float* __restrict a = static_cast<const float*>(k.u_a.data) + at;
    const float* __restrict b = static_cast<const float*>(k.u_b.data) + at;
#pragma omp simd
    for (int i = 0; i < n; ++i) t[i] = k.dotTerm(m[i], a[i], b[i]);
    k.partials[static_cast<std::size_t>(y + res.y * z)] = rowPartsOf<1>(k, t, n);
  }
};

}  // namespace

void addPcgDot(KernelRegistry& r) { r.add<CellRowRunner<K, DotRows>>("pcg_dot.comp", {}); }

}  // namespace hf::cpu::kernels
