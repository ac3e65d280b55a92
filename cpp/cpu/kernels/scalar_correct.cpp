// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_correct.comp built as C++ (cpu/kernel.h), run by a row loop (SimdRowRunner) over the
// shader's branch-free correctedValues, which GCC vectorizes. It reads its cell and the six around it; past the grid's edge those land in the textures'
// guard bands (cpu/cpu_device.cpp) and are not taken (no link there), so the loop runs the
// unchecked build.
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct ScalarCorrect : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_correct.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

struct ScalarCorrectRow {
  static glm::ivec3 box(ScalarCorrect& k, const glm::ivec3& n) { return glm::min(n, k.u_res); }
  void operator()(ScalarCorrect& k, int x, int y, int z) const {
    const glm::ivec3 c(x, y, z);
    const glm::vec2 v = k.correctedValues(c);
    glsl::imageStore(k.u_density_out, c, glm::vec4(v.x));
    glsl::imageStore(k.u_temperature_out, c, glm::vec4(v.y));
  }
};

}  // namespace

void addScalarCorrect(KernelRegistry& r) { r.add<SimdRowRunner<ScalarCorrect, ScalarCorrectRow>>("scalar_correct.comp", {}); }

}  // namespace hf::cpu::kernels
