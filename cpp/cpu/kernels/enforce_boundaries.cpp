// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/enforce_boundaries.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EnforceBoundaries : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addEnforceBoundaries(KernelRegistry& r) {
  r.add<InvocationRunner<EnforceBoundaries>>("enforce_boundaries.comp", {});
}

}  // namespace hf::cpu::kernels
