// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/cell_forces.comp built as C++ (cpu/kernel.h), run by a row loop (InteriorSimdRowRunner) over
// the shader's branch-free cellForce, which GCC vectorizes. Its lookups are clamped to the grid
// (clampCell), so every access is in range and the loop runs the unchecked build; the cells whose
// neighbours are all in the grid run it built with HF_CLAMP_FREE (no clamp: contiguous loads).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct CellForces : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "cell_forces.comp"
};

#define HF_CLAMP_FREE 1
struct CellForcesInterior : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "cell_forces.comp"
};
#undef HF_CLAMP_FREE

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct CellForcesRow {
  static glm::ivec3 box(CellForces& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  template <class K>
  void operator()(K& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_force, c, glm::vec4(k.cellForce(c), 0.0f));
  }
};

}  // namespace

void addCellForces(KernelRegistry& r) { r.add<InteriorSimdRowRunner<CellForces, CellForcesInterior, CellForcesRow>>("cell_forces.comp", {}); }

}  // namespace hf::cpu::kernels
