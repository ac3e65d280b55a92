// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/vorticity.comp built as C++ (cpu/kernel.h), run by a row loop (InteriorSimdRowRunner) over
// the shader's branch-free vorticityAt, which GCC vectorizes. Its lookups are clamped to the grid
// (clampCell), so every access is in range and the loop runs the unchecked build; the cells whose
// neighbours are all in the grid run it built with HF_CLAMP_FREE (no clamp: contiguous loads).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct Vorticity : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "vorticity.comp"
};

#define HF_CLAMP_FREE 1
struct VorticityInterior : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "vorticity.comp"
};
#undef HF_CLAMP_FREE

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct VorticityRow {
  static glm::ivec3 box(Vorticity& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  template <class K>
  void operator()(K& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_vorticity, c, glm::vec4(k.vorticityAt(c)));
  }
};

}  // namespace

void addVorticity(KernelRegistry& r) { r.add<InteriorSimdRowRunner<Vorticity, VorticityInterior, VorticityRow>>("vorticity.comp", {}); }

}  // namespace hf::cpu::kernels
