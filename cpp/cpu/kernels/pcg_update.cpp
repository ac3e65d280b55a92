// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_update.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PcgUpdate : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_update.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPcgUpdate(KernelRegistry& r) {
  r.add<InvocationRunner<PcgUpdate>>("pcg_update.comp", {});
}

}  // namespace hf::cpu::kernels
