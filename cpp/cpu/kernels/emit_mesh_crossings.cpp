// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/emit_mesh_crossings.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EmitMeshCrossings : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "emit_mesh_crossings.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addEmitMeshCrossings(KernelRegistry& r) {
  r.add<InvocationRunner<EmitMeshCrossings>>("emit_mesh_crossings.comp", {});
}

}  // namespace hf::cpu::kernels
