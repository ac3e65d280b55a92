// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/divergence.comp built as C++ (cpu/kernel.h), run by a row loop over the shader's
// branch-free divergenceRhs, which GCC vectorizes. It reads its cell's six faces and the clamped
// cells beside them, all in range; the inner cells run it built with HF_CLAMP_FREE
// (InteriorSimdRowRunner: no clamp, contiguous loads).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct Divergence : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "divergence.comp"
};

#define HF_CLAMP_FREE 1
struct DivergenceInterior : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "divergence.comp"
};
#undef HF_CLAMP_FREE

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct DivergenceRow {
  static glm::ivec3 box(Divergence& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  template <class K>
  void operator()(K& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_rhs, c, glm::vec4(k.divergenceRhs(c)));
  }
};

}  // namespace

void addDivergence(KernelRegistry& r) { r.add<InteriorSimdRowRunner<Divergence, DivergenceInterior, DivergenceRow>>("divergence.comp", {}); }

}  // namespace hf::cpu::kernels
