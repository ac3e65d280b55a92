// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/binary_fractions.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct BinaryFractions : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "binary_fractions.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addBinaryFractions(KernelRegistry& r) {
  r.add<InvocationRunner<BinaryFractions>>("binary_fractions.comp", {});
}

}  // namespace hf::cpu::kernels
