// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/sphere_fractions.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct SphereFractions : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "sphere_fractions.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addSphereFractions(KernelRegistry& r) {
  r.add<InvocationRunner<SphereFractions>>("sphere_fractions.comp", {});
}

}  // namespace hf::cpu::kernels
