// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_restrict.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgRestrict : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_restrict.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgRestrict(KernelRegistry& r) {
  r.add<InvocationRunner<MgRestrict>>("mg_restrict.comp", {});
}

}  // namespace hf::cpu::kernels
