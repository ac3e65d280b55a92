// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pressure_shift.comp built as C++ (cpu/kernel.h), run by a row loop (SimdRowRunner) over the
// shader's branch-free shiftedPressure, which GCC vectorizes. It reads and writes its own cell only.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PressureShift : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pressure_shift.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct PressureShiftRow {
  static glm::ivec3 box(PressureShift& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  void operator()(PressureShift& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_pressure, c, glm::vec4(k.shiftedPressure(c, k.fluidMean())));
  }
};

}  // namespace

void addPressureShift(KernelRegistry& r) { r.add<SimdRowRunner<PressureShift, PressureShiftRow>>("pressure_shift.comp", {}); }

}  // namespace hf::cpu::kernels
