// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/voxelize_mesh_crossings.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct VoxelizeMeshCrossings : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "voxelize_mesh_crossings.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addVoxelizeMeshCrossings(KernelRegistry& r) {
  r.add<InvocationRunner<VoxelizeMeshCrossings>>("voxelize_mesh_crossings.comp", {});
}

}  // namespace hf::cpu::kernels
