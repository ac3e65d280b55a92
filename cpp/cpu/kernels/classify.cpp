// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/classify.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct Classify : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "classify.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addClassify(KernelRegistry& r) {
  r.add<InvocationRunner<Classify>>("classify.comp", {});
}

}  // namespace hf::cpu::kernels
