// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/pcg_direction.comp built as C++ (cpu/kernel.h), run by a row loop (SimdRowRunner) over
// the shader's branch-free newDirection, which GCC vectorizes. Its accesses are its own cell's, so
// the loop runs the unchecked build.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct PcgDirection : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "pcg_direction.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct PcgDirectionRow {
  static glm::ivec3 box(PcgDirection& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  void operator()(PcgDirection& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    glsl::imageStore(k.u_s, c, glm::vec4(k.newDirection(c)));
  }
};

}  // namespace

void addPcgDirection(KernelRegistry& r) { r.add<SimdRowRunner<PcgDirection, PcgDirectionRow>>("pcg_direction.comp", {}); }

}  // namespace hf::cpu::kernels
