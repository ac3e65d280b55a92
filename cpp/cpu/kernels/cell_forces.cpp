// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/cell_forces.comp built as C++ (cpu/kernel.h).
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

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addCellForces(KernelRegistry& r) {
  r.add<InvocationRunner<CellForces>>("cell_forces.comp", {});
}

}  // namespace hf::cpu::kernels
