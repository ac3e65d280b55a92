// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/apply_forces.comp built as C++ (cpu/kernel.h), run by a row loop over the shader's
// branch-free acceleratedVelocity, which GCC vectorizes. Its lookups are clamped to the grid, so
// every access is in range; the faces whose two cells are inner cells run it built with
// HF_CLAMP_FREE (InteriorSimdRowRunner: no clamp, contiguous loads).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct ApplyForces : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "apply_forces.comp"
};

#define HF_CLAMP_FREE 1
struct ApplyForcesInterior : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "apply_forces.comp"
};
#undef HF_CLAMP_FREE

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct ApplyForcesRow {
  static constexpr bool kPerAxis = true;  // one loop per axis (cpu/kernel.h, PerAxis)
  static glm::ivec3 box(ApplyForces& k, const glm::ivec3& n) { return glm::min(n, k.faceSize(k.u_axis)); }
  template <class K>
  void operator()(K& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_vel, c, glm::vec4(k.acceleratedVelocity(c)));
  }
};

}  // namespace

void addApplyForces(KernelRegistry& r) { r.add<InteriorSimdRowRunner<ApplyForces, ApplyForcesInterior, ApplyForcesRow>>("apply_forces.comp", {}); }

}  // namespace hf::cpu::kernels
