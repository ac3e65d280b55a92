// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/maccormack.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct Maccormack : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "maccormack.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMaccormack(KernelRegistry& r) {
  r.add<InvocationRunner<Maccormack>>("maccormack.comp", {});
}

}  // namespace hf::cpu::kernels
