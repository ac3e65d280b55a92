// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/emit_coverage.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EmitCoverage : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "emit_coverage.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addEmitCoverage(KernelRegistry& r) {
  r.add<InvocationRunner<EmitCoverage>>("emit_coverage.comp", {});
}

}  // namespace hf::cpu::kernels
