// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_direction.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PcgDirection : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_direction.comp"
};

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgDirectionUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_direction.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPcgDirection(KernelRegistry& r) {
  r.add<InteriorRunner<PcgDirection, PcgDirectionUnchecked>>("pcg_direction.comp", {});
}

}  // namespace hf::cpu::kernels
