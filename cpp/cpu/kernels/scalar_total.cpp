// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_total.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct ScalarTotal : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_total.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addScalarTotal(KernelRegistry& r) {
  r.add<InvocationRunner<ScalarTotal>>("scalar_total.comp", {});
}

}  // namespace hf::cpu::kernels
