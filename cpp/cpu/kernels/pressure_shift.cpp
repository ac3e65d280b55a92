// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pressure_shift.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PressureShift : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pressure_shift.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPressureShift(KernelRegistry& r) {
  r.add<InvocationRunner<PressureShift>>("pressure_shift.comp", {});
}

}  // namespace hf::cpu::kernels
