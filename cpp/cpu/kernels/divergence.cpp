// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/divergence.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct Divergence : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "divergence.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addDivergence(KernelRegistry& r) {
  r.add<InvocationRunner<Divergence>>("divergence.comp", {});
}

}  // namespace hf::cpu::kernels
