// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_total.comp built as C++ (cpu/kernel.h).
// A row stage: every access is in range by the shader's own construction (a loop over its row
// of the grid that reads neighbours only across linked faces), so it runs unchecked, its rows
// over every thread (RowLoopRunner).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct ScalarTotalUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_total.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addScalarTotal(KernelRegistry& r) {
  r.add<RowLoopRunner<ScalarTotalUnchecked>>("scalar_total.comp", {});
}

}  // namespace hf::cpu::kernels
