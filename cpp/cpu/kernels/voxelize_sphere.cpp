// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/voxelize_sphere.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct VoxelizeSphere : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "voxelize_sphere.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addVoxelizeSphere(KernelRegistry& r) {
  r.add<InvocationRunner<VoxelizeSphere>>("voxelize_sphere.comp", {});
}

}  // namespace hf::cpu::kernels
