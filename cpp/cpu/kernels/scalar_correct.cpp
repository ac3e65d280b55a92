// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_correct.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct ScalarCorrect : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_correct.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addScalarCorrect(KernelRegistry& r) {
  r.add<InvocationRunner<ScalarCorrect>>("scalar_correct.comp", {});
}

}  // namespace hf::cpu::kernels
