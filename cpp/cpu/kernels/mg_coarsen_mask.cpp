// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_coarsen_mask.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested. A dispatch of a box from u_origin
// (MultigridVCycle::buildMasks) lies in the grid, so its interior lies in the grid's.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgCoarsenMask : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_coarsen_mask.comp"
};

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct MgCoarsenMaskUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_coarsen_mask.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgCoarsenMask(KernelRegistry& r) {
  r.add<InteriorRunner<MgCoarsenMask, MgCoarsenMaskUnchecked>>("mg_coarsen_mask.comp", {});
}

}  // namespace hf::cpu::kernels
