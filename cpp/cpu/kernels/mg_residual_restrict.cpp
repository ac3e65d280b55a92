// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_residual_restrict.comp built as C++ (cpu/kernel.h), with a row loop of its own: it is
// the largest multigrid stage after the smoothing. Per row of coarse cells, the four fine rows
// under it get their residuals from the shader's residualAt (vectorized over each fine row:
// cpu/kernels/pressure_row.h says why its loads need no bounds tests), then each coarse cell
// adds its eight children's in the shader's order (bits of o: x, y, z), a child past the fine
// grid as 0 (the shader leaves it out: adding 0 is exact), the same bits as the GPU.
#include "cpu/kernels/kernel_list.h"

#include <algorithm>
#include <vector>

#include "cpu/kernels/pressure_row.h"
#include "cpu/regular_rows.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct MgResidualRestrictUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_residual_restrict.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = MgResidualRestrictUnchecked;

class ResidualRestrictRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 coarse = kernel_.u_res;
    const glm::ivec3 fine = kernel_.u_fine_size;
    constexpr const char* stage = "mg_residual_restrict";
    checkBound(kernel_.u_x, fine, stage, "x");
    checkBound(kernel_.u_b, fine, stage, "b");
    checkBound(kernel_.u_mask, fine, stage, "mask");
    checkBound(kernel_.u_faces, fine + 1, stage, "faces");
    checkBound(kernel_.u_coarse_b, coarse, stage, "coarse b");
    const std::uint8_t* open = bindings.regular_rows->flags(kernel_.u_mask, kernel_.u_faces, fine, pool, bindings.x86_v3);
    forRows(
        glm::ivec3(1, coarse.y, coarse.z), pool,
        [&](int y, int z) { runBest(bindings.x86_v3, [&] { row(y, z, coarse, fine, open); }); }, [](int, int) {},
        8LL * coarse.x);
  }

 private:
  // (always_inline: flattened into each instruction set's build by runBest.)
  // `open`: the fine rows' flags (cpu/regular_rows.h): an open row's inner cells take kAllLinks
  // and unit fractions as constants, its end cells too where they are against a wall on x.
  __attribute__((always_inline)) void row(int y, int z, const glm::ivec3& coarse, const glm::ivec3& fine,
                                          const std::uint8_t* open) const {
    K k(kernel_);
    const int width = 2 * coarse.x;  // at least fine.x; children past it are 0
    thread_local std::vector<float> buffer;
    buffer.assign(static_cast<std::size_t>(4 * width), 0.0f);
    const float* b = static_cast<const float*>(k.u_b.data);
    for (int q = 0; q < 4; ++q) {  // fine row (2y + (q & 1), 2z + (q >> 1)): children with o = dx + 2 q
      const int fy = 2 * y + (q & 1), fz = 2 * z + (q >> 1);
      if (fy >= fine.y || fz >= fine.z) continue;
      const PressureRow p(k.u_mask, k.u_faces, k.u_x, fine, fy, fz);
      float* __restrict r = buffer.data() + q * width;
      const int n = std::min(fine.x, width);  // fine cells past 2 coarse.x have no parent
      if ((open[fy + fz * fine.y] & kOpenInside) != 0 && n == fine.x) {
        const glm::vec3 unit(1.0f);
#pragma omp simd
        for (int i = 1; i < n - 1; ++i) {
          r[i] = k.residualAt(kAllLinks, unit, unit, p.x(i), p.xLo(i), p.xHi(i), b[p.cell(i)]);
        }
        for (int i : {0, n - 1}) {
          const PressureRow::Links e = p.endLinks(i, open[fy + fz * fine.y], n);
          r[i] = k.residualAt(e.mask, e.lo, e.hi, p.x(i), p.xLo(i), p.xHi(i), b[p.cell(i)]);
        }
      } else {
#pragma omp simd
        for (int i = 0; i < n; ++i) {
          r[i] = k.residualAt(p.mask(i), p.facesLo(i), p.facesHi(i), p.x(i), p.xLo(i), p.xHi(i), b[p.cell(i)]);
        }
      }
    }
    const float* __restrict r0 = buffer.data();
    const float* __restrict r1 = r0 + width;
    const float* __restrict r2 = r1 + width;
    const float* __restrict r3 = r2 + width;
    float* __restrict out = static_cast<float*>(k.u_coarse_b.data) + k.u_coarse_b.index(glm::ivec3(0, y, z));
    const float scale = k.u_scale;
#pragma omp simd
    for (int x = 0; x < coarse.x; ++x) {
      float sum = 0.0f;
      sum += r0[2 * x];
      sum += r0[2 * x + 1];
      sum += r1[2 * x];
      sum += r1[2 * x + 1];
      sum += r2[2 * x];
      sum += r2[2 * x + 1];
      sum += r3[2 * x];
      sum += r3[2 * x + 1];
      out[x] = scale * sum;
    }
  }

  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace

void addMgResidualRestrict(KernelRegistry& r) {
  r.add<ResidualRestrictRows>("mg_residual_restrict.comp", {});
}

}  // namespace hf::cpu::kernels
