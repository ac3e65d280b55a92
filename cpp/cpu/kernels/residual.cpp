// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/residual.comp built as C++ (cpu/kernel.h).
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

struct ResidualUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "residual.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addResidual(KernelRegistry& r) {
  r.add<RowLoopRunner<ResidualUnchecked>>("residual.comp", {});
}

}  // namespace hf::cpu::kernels
