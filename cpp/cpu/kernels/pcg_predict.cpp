// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_predict.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage: one
// invocation per row of cells, run by pressure_row.h's CellRowRunner). The shader's predictCell gives
// every cell's starting p and r and its terms of the row's sums, vectorized over the row (a cell reads only itself), summed by
// parts (rowPartsOf, common.glsl's ROW_PARTS) as the shader sums them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgPredictUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_predict.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PcgPredictUnchecked;

struct PredictRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_predict";
    checkBound(kernel.u_pressure, res, stage, "pressure");
    checkBound(kernel.u_r, res, stage, "r");
    checkBound(kernel.u_rhs, res, stage, "rhs");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res) {
    const int n = res.x;
    const int at = rowStart(res, y, z);
    const std::uint8_t* __restrict m = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    float* __restrict t = termRows<4>(n);
    float* __restrict p = static_cast<float*>(k.u_pressure.data) + at;
    float* __restrict r = static_cast<float*>(k.u_r.data) + at;
    const float* __restrict rhs = static_cast<const float*>(k.u_rhs.data) + at;
    const float alpha = k.predictorAlpha(k.results[k.u_slot_ap]);
    const float mean = k.residualMean();
#pragma omp simd
    for (int i = 0; i < n; ++i) {
      float pi = p[i], ri = r[i];
      const glm::vec4 v = k.predictCell(m[i], alpha, mean, -rhs[i], pi, ri);
      p[i] = pi;
      r[i] = ri;
      t[i] = v.x;
      t[n + i] = v.y;
      t[2 * n + i] = v.z;
      t[3 * n + i] = v.w;
    }
    k.partials[static_cast<std::size_t>(y + res.y * z)] = rowPartsOf<4>(k, t, n);
  }
};

}  // namespace

void addPcgPredict(KernelRegistry& r) { r.add<CellRowRunner<K, PredictRows>>("pcg_predict.comp", {}); }

}  // namespace hf::cpu::kernels
