// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_smooth.comp built as C++ (cpu/kernel.h).
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

#define PROLONG 1
struct MgSmoothProlong : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef PROLONG

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addMgSmooth(KernelRegistry& r) {
  r.add<InvocationRunner<MgSmooth>>("mg_smooth.comp", {});
  r.add<InvocationRunner<MgSmoothProlong>>("mg_smooth.comp", {{"PROLONG", "1"}});
}

}  // namespace hf::cpu::kernels
