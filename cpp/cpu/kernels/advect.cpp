// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/advect.comp built as C++ (cpu/kernel.h).
// Every access is in range by the shader's own construction (clamped coordinates; or a loop
// over its row of the grid that reads neighbours only across linked faces), so it runs
// unchecked (UncheckedRunner).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

#define FIELD_AT 0
struct AdvectUUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 1
struct AdvectVUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 2
struct AdvectWUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
struct AdvectScalarUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
#define PAIR 1
struct AdvectPairUnchecked : KernelBase {
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
  r.add<UncheckedRunner<AdvectUUnchecked>>("advect.comp", {{"FIELD_AT", "0"}});
  r.add<UncheckedRunner<AdvectVUnchecked>>("advect.comp", {{"FIELD_AT", "1"}});
  r.add<UncheckedRunner<AdvectWUnchecked>>("advect.comp", {{"FIELD_AT", "2"}});
  r.add<UncheckedRunner<AdvectScalarUnchecked>>("advect.comp", {{"FIELD_AT", "3"}});
  r.add<UncheckedRunner<AdvectPairUnchecked>>("advect.comp", {{"FIELD_AT", "3"}, {"PAIR", "1"}});
}

}  // namespace hf::cpu::kernels
