// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/emit_mesh_coverage.comp built as C++ (cpu/kernel.h).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EmitMeshCoverage : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "emit_mesh_coverage.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

void addEmitMeshCoverage(KernelRegistry& r) {
  r.add<InvocationRunner<EmitMeshCoverage>>("emit_mesh_coverage.comp", {});
}

}  // namespace hf::cpu::kernels
