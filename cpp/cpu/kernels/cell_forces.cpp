// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/cell_forces.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct CellForces : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "cell_forces.comp"
};

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct CellForcesUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "cell_forces.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addCellForces(KernelRegistry& r) {
  r.add<InteriorRunner<CellForces, CellForcesUnchecked>>("cell_forces.comp", {});
}

}  // namespace hf::cpu::kernels
