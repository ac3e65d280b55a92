// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_update.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage: one
// invocation per row of cells, run by pressure_row.h's CellRowRunner). The shader's updateCell gives
// every cell's p and r and its terms of the row's sums, vectorized over the row (a cell reads only itself), summed by
// parts (rowPartsOf, common.glsl's ROW_PARTS) as the shader sums them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgUpdateUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_update.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PcgUpdateUnchecked;

struct UpdateRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_update";
    checkBound(kernel.u_pressure, res, stage, "pressure");
    checkBound(kernel.u_r, res, stage, "r");
    checkBound(kernel.u_s, res, stage, "s");
    checkBound(kernel.u_q, res, stage, "q");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res) {
    const int n = res.x;
    const int at = rowStart(res, y, z);
    const std::uint8_t* __restrict m = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    float* __restrict t = termRows<3>(n);
    float* __restrict p = static_cast<float*>(k.u_pressure.data) + at;
    float* __restrict r = static_cast<float*>(k.u_r.data) + at;
    const float* __restrict s = static_cast<const float*>(k.u_s.data) + at;
    const float* __restrict q = static_cast<const float*>(k.u_q.data) + at;
    const float alpha = k.stepAlpha();
#pragma omp simd
    for (int i = 0; i < n; ++i) {
      float pi = p[i], ri = r[i];
      const glm::vec4 v = k.updateCell(m[i], alpha, s[i], q[i], pi, ri);
      p[i] = pi;
      r[i] = ri;
      t[i] = v.x;
      t[n + i] = v.y;
      t[2 * n + i] = v.z;
    }
    k.partials[static_cast<std::size_t>(y + res.y * z)] = rowPartsOf<3>(k, t, n);
  }
};

}  // namespace

void addPcgUpdate(KernelRegistry& r) { r.add<CellRowRunner<K, UpdateRows>>("pcg_update.comp", {}); }

}  // namespace hf::cpu::kernels
