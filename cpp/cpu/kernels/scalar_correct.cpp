// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_correct.comp built as C++ (cpu/kernel.h), with a row loop of its own over the
// shader's branch-free correctedFrom, which GCC vectorizes: the step's fractions (stepFractions)
// once a dispatch, and a row's inner cells, where all are linked to their six neighbours (most
// rows), with the mask kAllLinks as a constant, so the bit tests and the selects fold away (the
// same max and min of the same values: the same bits). It reads its cell and the six around it;
// past the grid's edge those land in the textures' guard bands (cpu/cpu_device.cpp) and are not
// taken (no link there), so the loop runs the unchecked build.
#include "cpu/kernels/kernel_list.h"

#include <cstdint>

#include "cpu/regular_rows.h"  // kAllLinks, byLinkedInside

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

using K = ScalarCorrect;

class CorrectRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 box = glm::min(n, kernel_.u_res);
    if (box.x <= 0 || box.y <= 0 || box.z <= 0) return;
    const glm::vec4 f = kernel_.stepFractions();
    const glm::vec2 fd(f.x, f.y), ft(f.z, f.w);
    const int nx = kernel_.u_res.x;
    forEachRow(box, pool, bindings.x86_v3, kernel_,
               [&](K& k, int y, int z, int x0, int x1) { row(k, y, z, x0, x1, nx, fd, ft); });
  }

 private:
  // Cells x0 .. x1 - 1 of row (y, z). (always_inline: flattened into each instruction set's build
  // by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, int x0, int x1, int nx, glm::vec2 fd,
                                                 glm::vec2 ft) {
    const glm::ivec3 first(0, y, z);
    const float* d = static_cast<const float*>(k.u_density.data) + k.u_density.index(first);
    const float* t = static_cast<const float*>(k.u_temperature.data) + k.u_temperature.index(first);
    const std::uint8_t* nb = static_cast<const std::uint8_t*>(k.u_nbmask.data) + k.u_nbmask.index(first);
    float* d_out = static_cast<float*>(k.u_density_out.data) + k.u_density_out.index(first);
    float* t_out = static_cast<float*>(k.u_temperature_out.data) + k.u_temperature_out.index(first);
    byLinkedInside(nb, x0, x1, nx, [&](auto linked, int b, int e) {
      cells<decltype(linked)::value>(k, y, z, b, e, d, t, nb, d_out, t_out, fd, ft);
    });
  }

  // Cells b .. e - 1 of row (y, z): the mask kAllLinks as a constant where kLinked, else loaded.
  template <bool kLinked>
  __attribute__((always_inline)) static void cells(K& k, int y, int z, int b, int e, const float* __restrict d,
                                                   const float* __restrict t, const std::uint8_t* __restrict nb,
                                                   float* __restrict d_out, float* __restrict t_out, glm::vec2 fd,
                                                   glm::vec2 ft) {
#pragma omp simd
    for (int i = b; i < e; ++i) {
      const std::uint32_t mask = kLinked ? kAllLinks : nb[i];
      const glm::vec2 v = k.correctedFrom(glm::ivec3(i, y, z), glm::vec2(d[i], t[i]), mask, fd, ft);
      d_out[i] = v.x;
      t_out[i] = v.y;
    }
  }

  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace

void addScalarCorrect(KernelRegistry& r) { r.add<CorrectRows>("scalar_correct.comp", {}); }

}  // namespace hf::cpu::kernels
