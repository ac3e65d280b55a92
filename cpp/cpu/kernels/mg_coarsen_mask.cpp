// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_coarsen_mask.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgCoarsenMask : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_coarsen_mask.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgCoarsenMask(KernelRegistry& r) {
  r.add<InvocationRunner<MgCoarsenMask>>("mg_coarsen_mask.comp", {});
}

}  // namespace hf::cpu::kernels
