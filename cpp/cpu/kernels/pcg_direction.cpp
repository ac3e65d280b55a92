// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_direction.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PcgDirection : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_direction.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPcgDirection(KernelRegistry& r) {
  r.add<InvocationRunner<PcgDirection>>("pcg_direction.comp", {});
}

}  // namespace hf::cpu::kernels
