// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_residual.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgResidual : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_residual.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgResidual(KernelRegistry& r) {
  r.add<InvocationRunner<MgResidual>>("mg_residual.comp", {});
}

}  // namespace hf::cpu::kernels
