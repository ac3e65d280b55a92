// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_direction.comp built as C++ (cpu/kernel.h), run by a row loop (CellRowRunner) over
// the shader's branch-free newDirection, which GCC vectorizes, with the shader's beta taken once a
// row (per cell, its two loads from the results and its division could not leave the loop: the
// stores to s might alias them). Its accesses are its own cell's, so the loop runs the unchecked
// build.
#include "cpu/kernels/kernel_list.h"

#include <cstdint>

#include "cpu/kernels/pressure_row.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgDirection : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_direction.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct DirectionRows {
  static void check(const PcgDirection& kernel, const glm::ivec3& res) {
    constexpr const char* stage = "pcg_direction";
    checkBound(kernel.u_s, res, stage, "s");
    checkBound(kernel.u_z, res, stage, "z");
    checkBound(kernel.u_nbmask, res, stage, "nbmask");
  }

  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(PcgDirection& k, int y, int z, const glm::ivec3& res) {
    const int at = rowStart(res, y, z);
    const std::uint8_t* __restrict m = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    const float* __restrict zz = static_cast<const float*>(k.u_z.data) + at;
    float* __restrict s = static_cast<float*>(k.u_s.data) + at;
    const float beta = k.directionBeta();
#pragma omp simd
    for (int i = 0; i < res.x; ++i) s[i] = k.newDirection(m[i], zz[i], s[i], beta);
  }
};

}  // namespace

void addPcgDirection(KernelRegistry& r) { r.add<CellRowRunner<PcgDirection, DirectionRows>>("pcg_direction.comp", {}); }

}  // namespace hf::cpu::kernels
