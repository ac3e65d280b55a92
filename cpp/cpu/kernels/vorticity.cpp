// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/vorticity.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct Vorticity : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "vorticity.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addVorticity(KernelRegistry& r) {
  r.add<InvocationRunner<Vorticity>>("vorticity.comp", {});
}

}  // namespace hf::cpu::kernels
