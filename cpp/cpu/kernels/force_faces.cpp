// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/force_faces.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#define GROUP_SUM 1
struct ForceFaces : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "force_faces.comp"
};
#undef GROUP_SUM

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addForceFaces(KernelRegistry& r) {
  r.add<GroupSumRunner<ForceFaces>>("force_faces.comp", {{"GROUP_SUM", "1"}});
}

}  // namespace hf::cpu::kernels
