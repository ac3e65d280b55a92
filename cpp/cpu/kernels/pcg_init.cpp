// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_init.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage:
// one invocation per row of cells, run by pressure_row.h's PressureRowRunner). The shader's
// startResidual gives every cell's residual, vectorized over the row (cpu/kernels/pressure_row.h
// says why its loads need no bounds tests); its startSums and startApSums, vectorized too, give
// the cells' terms, summed by parts (addRowParts, common.glsl's ROW_PARTS) as the shader sums
// them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"


#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgInitUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_init.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PcgInitUnchecked;

struct InitRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_init";
    checkBound(kernel.u_pressure, res, stage, "pressure");
    checkBound(kernel.u_rhs, res, stage, "rhs");
    checkBound(kernel.u_r, res, stage, "r");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
    checkBound(kernel.u_face_open, res + 1, stage, "face_open");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  // An open row's inner cells take kAllLinks and unit fractions as constants, its end cells too
  // where they are against a wall on x (cpu/regular_rows.h).
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res, std::uint8_t flags) {
    float* __restrict bs = termRows<10>(res.x);
    float* __restrict aps = bs + res.x;
    float* __restrict terms = aps + res.x;  // 7 rows: startSums' x y z w, startApSums' x y z
    const PressureRow p(k.u_nbmask, k.u_face_open, k.u_pressure, res, y, z);
    const float* __restrict rhs = static_cast<const float*>(k.u_rhs.data) + p.cell(0);
    // The row's r, or where it is not stored (u_store_r 0) the buffer's last row.
    float* __restrict r = k.u_store_r != 0 ? static_cast<float*>(k.u_r.data) + p.cell(0) : terms + 7 * res.x;
    if ((flags & kOpenInside) != 0) {
      const glm::vec3 unit(1.0f);
#pragma omp simd
      for (int i = 1; i < res.x - 1; ++i) {
        r[i] = k.startResidual(kAllLinks, unit, unit, p.x(i), p.xLo(i), p.xHi(i), rhs[i], bs[i], aps[i]);
      }
      for (int i : {0, res.x - 1}) {
        const PressureRow::Links e = p.endLinks(i, flags, res.x);
        r[i] = k.startResidual(e.mask, e.lo, e.hi, p.x(i), p.xLo(i), p.xHi(i), rhs[i], bs[i], aps[i]);
      }
    } else {
#pragma omp simd
      for (int i = 0; i < res.x; ++i) {
        r[i] = k.startResidual(p.mask(i), p.facesLo(i), p.facesHi(i), p.x(i), p.xLo(i), p.xHi(i), rhs[i], bs[i], aps[i]);
      }
    }
#pragma omp simd
    for (int i = 0; i < res.x; ++i) {
      const glm::vec4 s = k.startSums(p.mask(i), r[i], bs[i]);
      terms[i] = s.x;
      terms[res.x + i] = s.y;
      terms[2 * res.x + i] = s.z;
      terms[3 * res.x + i] = s.w;
    }
    const std::size_t at = static_cast<std::size_t>(y + res.y * z);
    k.partials[at] = rowPartsOf<4>(k, terms, res.x);
    if (k.u_predictor_sums == 0) return;
#pragma omp simd
    for (int i = 0; i < res.x; ++i) {
      const glm::vec4 a = k.startApSums(p.mask(i), r[i], bs[i], aps[i]);
      terms[4 * res.x + i] = a.x;
      terms[5 * res.x + i] = a.y;
      terms[6 * res.x + i] = a.z;
    }
    const std::size_t rows = static_cast<std::size_t>(res.y) * static_cast<std::size_t>(res.z);
    k.partials[rows + at] = rowPartsOf<3>(k, terms + 4 * res.x, res.x);
  }
};

}  // namespace

void addPcgInit(KernelRegistry& r) { r.add<PressureRowRunner<K, InitRows>>("pcg_init.comp", {}); }

}  // namespace hf::cpu::kernels
