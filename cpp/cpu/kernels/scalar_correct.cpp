// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_correct.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested.
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

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct ScalarCorrectUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_correct.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addScalarCorrect(KernelRegistry& r) {
  r.add<InteriorRunner<ScalarCorrect, ScalarCorrectUnchecked>>("scalar_correct.comp", {});
}

}  // namespace hf::cpu::kernels
