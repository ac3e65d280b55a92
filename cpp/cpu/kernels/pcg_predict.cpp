// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_predict.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct PcgPredict : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_predict.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addPcgPredict(KernelRegistry& r) {
  r.add<InvocationRunner<PcgPredict>>("pcg_predict.comp", {});
}

}  // namespace hf::cpu::kernels
