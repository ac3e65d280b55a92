// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/voxelize_mesh_fill.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct VoxelizeMeshFill : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "voxelize_mesh_fill.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addVoxelizeMeshFill(KernelRegistry& r) {
  r.add<InvocationRunner<VoxelizeMeshFill>>("voxelize_mesh_fill.comp", {});
}

}  // namespace hf::cpu::kernels
