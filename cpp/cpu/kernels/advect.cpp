// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/advect.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#define FIELD_AT 0
struct AdvectU : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 1
struct AdvectV : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 2
struct AdvectW : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
struct AdvectScalar : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
#define PAIR 1
struct AdvectPair : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT
#undef PAIR

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addAdvect(KernelRegistry& r) {
  r.add<InvocationRunner<AdvectU>>("advect.comp", {{"FIELD_AT", "0"}});
  r.add<InvocationRunner<AdvectV>>("advect.comp", {{"FIELD_AT", "1"}});
  r.add<InvocationRunner<AdvectW>>("advect.comp", {{"FIELD_AT", "2"}});
  r.add<InvocationRunner<AdvectScalar>>("advect.comp", {{"FIELD_AT", "3"}});
  r.add<InvocationRunner<AdvectPair>>("advect.comp", {{"FIELD_AT", "3"}, {"PAIR", "1"}});
}

}  // namespace hf::cpu::kernels
