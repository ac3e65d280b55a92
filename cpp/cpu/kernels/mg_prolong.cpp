// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_prolong.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgProlong : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_prolong.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgProlong(KernelRegistry& r) {
  r.add<InvocationRunner<MgProlong>>("mg_prolong.comp", {});
}

}  // namespace hf::cpu::kernels
