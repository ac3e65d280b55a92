// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/project.comp built as C++ (cpu/kernel.h), run by a row loop (SimdRowRunner) over the
// shader's branch-free projectedVelocity, which GCC vectorizes. It reads the face and its two cells; at the domain's walls one of them is a cell
// past the grid, which lands in the textures' guard band and is not used.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct Project : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "project.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct ProjectRow {
  static constexpr bool kPerAxis = true;  // one loop per axis (cpu/kernel.h, PerAxis)
  static glm::ivec3 box(Project& k, const glm::ivec3& n) { return glm::min(n, k.faceSize(k.u_axis)); }
  void operator()(Project& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_vel, c, glm::vec4(k.projectedVelocity(c)));
  }
};

}  // namespace

void addProject(KernelRegistry& r) { r.add<SimdRowRunner<Project, ProjectRow>>("project.comp", {}); }

}  // namespace hf::cpu::kernels
