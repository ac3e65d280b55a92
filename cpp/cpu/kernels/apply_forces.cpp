// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/apply_forces.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct ApplyForces : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "apply_forces.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addApplyForces(KernelRegistry& r) {
  r.add<InvocationRunner<ApplyForces>>("apply_forces.comp", {});
}

}  // namespace hf::cpu::kernels
