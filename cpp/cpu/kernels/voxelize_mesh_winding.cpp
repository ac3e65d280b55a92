// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/voxelize_mesh_winding.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct VoxelizeMeshWinding : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "voxelize_mesh_winding.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addVoxelizeMeshWinding(KernelRegistry& r) {
  r.add<InvocationRunner<VoxelizeMeshWinding>>("voxelize_mesh_winding.comp", {});
}

}  // namespace hf::cpu::kernels
