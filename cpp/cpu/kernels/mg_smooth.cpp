// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_smooth.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// (InteriorRunner) and the shell around it bounds-tested.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct MgSmooth : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant

#define PROLONG 1
struct MgSmoothProlong : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant
#undef PROLONG

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct MgSmoothUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant

#define PROLONG 1
struct MgSmoothProlongUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant
#undef PROLONG

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgSmooth(KernelRegistry& r) {
  r.add<InteriorRunner<MgSmooth, MgSmoothUnchecked>>("mg_smooth.comp", {});
  r.add<InteriorRunner<MgSmoothProlong, MgSmoothProlongUnchecked>>("mg_smooth.comp", {{"PROLONG", "1"}});
}

}  // namespace hf::cpu::kernels
