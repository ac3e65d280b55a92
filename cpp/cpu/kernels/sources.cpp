// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/sources.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct Sources : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "sources.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addSources(KernelRegistry& r) {
  r.add<InvocationRunner<Sources>>("sources.comp", {});
}

}  // namespace hf::cpu::kernels
