// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pressure_sum.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PressureSum : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pressure_sum.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPressureSum(KernelRegistry& r) {
  r.add<InvocationRunner<PressureSum>>("pressure_sum.comp", {});
}

}  // namespace hf::cpu::kernels
