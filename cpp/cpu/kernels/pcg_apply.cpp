// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_apply.comp built as C++ (cpu/kernel.h), with a row loop of its own (a row stage:
// one invocation per row of cells, run by pressure_row.h's PressureRowRunner). The shader's
// appliedValues gives every cell's q = A s and its part of s.q, vectorized over the row
// (cpu/kernels/pressure_row.h says why its loads need no bounds tests); the parts are then
// summed by parts (addRowParts, common.glsl's ROW_PARTS) as the shader sums them: the GPU's bits.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgApplyUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_apply.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = PcgApplyUnchecked;

struct ApplyRows {
  static void check(const K& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_apply";
    checkBound(kernel.u_s, res, stage, "s");
    checkBound(kernel.u_q, res, stage, "q");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
    checkBound(kernel.u_face_open, res + 1, stage, "face_open");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  // An open row's inner cells take kAllLinks and unit fractions as constants, its end cells too
  // where they are against a wall on x (cpu/regular_rows.h).
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res, std::uint8_t flags) {
    float* __restrict part = termRows<1>(res.x);
    const PressureRow s(k.u_nbmask, k.u_face_open, k.u_s, res, y, z);
    float* __restrict q = static_cast<float*>(k.u_q.data) + s.cell(0);
    if ((flags & kOpenInside) != 0) {
      const glm::vec3 unit(1.0f);
#pragma omp simd
      for (int i = 1; i < res.x - 1; ++i) {
        const glm::vec2 v = k.appliedValues(kAllLinks, unit, unit, s.x(i), s.xLo(i), s.xHi(i));
        q[i] = v.x;
        part[i] = v.y;
      }
      for (int i : {0, res.x - 1}) {
        const PressureRow::Links e = s.endLinks(i, flags, res.x);
        const glm::vec2 v = k.appliedValues(e.mask, e.lo, e.hi, s.x(i), s.xLo(i), s.xHi(i));
        q[i] = v.x;
        part[i] = v.y;
      }
    } else {
#pragma omp simd
      for (int i = 0; i < res.x; ++i) {
        const glm::vec2 v = k.appliedValues(s.mask(i), s.facesLo(i), s.facesHi(i), s.x(i), s.xLo(i), s.xHi(i));
        q[i] = v.x;
        part[i] = v.y;
      }
    }
    k.partials[static_cast<std::size_t>(y + res.y * z)] = rowPartsOf<1>(k, part, res.x);
  }
};

}  // namespace

void addPcgApply(KernelRegistry& r) { r.add<PressureRowRunner<K, ApplyRows>>("pcg_apply.comp", {}); }

}  // namespace hf::cpu::kernels
