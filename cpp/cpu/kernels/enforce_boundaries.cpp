// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/enforce_boundaries.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EnforceBoundaries : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct EnforceBoundariesUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addEnforceBoundaries(KernelRegistry& r) {
  r.add<InteriorRunner<EnforceBoundaries, EnforceBoundariesUnchecked>>("enforce_boundaries.comp", {});
}

}  // namespace hf::cpu::kernels
