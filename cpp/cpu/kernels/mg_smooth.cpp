// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_smooth.comp built as C++ (cpu/kernel.h), with a row loop of its own: the smoothing
// sweeps are most of a multigrid solve. The loop walks one row of cells of the sweep's colour,
// loads each cell's neighbourhood from the arrays and calls the shader's smoothedValue, the
// per-cell arithmetic the GPU runs too (the same bits). Loads past the grid's edge land in the
// textures' guard bands and are not used (the cell has no link there), so no bounds tests.
// A row whose inner cells (1 .. nx - 2) are all fluid with six links and six wholly open faces (most
// rows away from the walls and the probe) calls smoothedValue with that mask and those fractions
// as constants (cpu/regular_rows.h), so the mask's bit tests fold away and neither mask nor faces
// is read for them. With w = 1 the shader's sums are the same bits (1 * x is x; n adds six 1s).
#include "cpu/kernels/kernel_list.h"

#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include "common/error.h"
#include "cpu/regular_rows.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct MgSmooth : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant

#define PROLONG 1
struct MgSmoothProlong : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef PROLONG
#undef NEIGHBOUR_X

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

template <class T>
T* texels(const ImageBinding& image) {
  return static_cast<T*>(image.data);
}

void checkSize(const ImageBinding& image, const glm::ivec3& want, const char* name) {
  if (image.data == nullptr || image.size != want) {
    throw Error(std::string("mg_smooth: image ") + name + " is not bound at the level's size");
  }
}

template <class K, bool kProlong>
class SmoothRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 res = kernel_.u_res;
    checkSize(kernel_.u_x, res, "x");
    checkSize(kernel_.u_b, res, "b");
    checkSize(kernel_.u_mask, res, "mask");
    checkSize(kernel_.u_faces, res + 1, "faces");
    glm::ivec3 coarse(0);
    if constexpr (kProlong) {
      coarse = kernel_.u_coarse_x.size;
      if (kernel_.u_coarse_x.data == nullptr || glm::any(glm::lessThan(coarse * 2, res))) {
        throw Error("mg_smooth: the coarse x is not bound at the next level's size");
      }
    }
    const std::uint8_t* regular = bindings.regular_rows->flags(kernel_.u_mask, kernel_.u_faces, res, pool);
    forRows(glm::ivec3(res.x, res.y, res.z), pool,
            [&](int y, int z) { runBest(bindings.x86_v3, [&] { row(y, z, res, coarse, regular[y + z * res.y] != 0); }); },
            [](int, int) {});
  }

 private:
  // Every cell of the row is computed (contiguous loads vectorize; strided ones do not) into a
  // row buffer that keeps the other colour's old values, then copied back: the loop reads x
  // and writes elsewhere. The other colour's cells are the only ones a cell reads, and they do
  // not change, so the copy's timing does not matter.
  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) void row(int y, int z, const glm::ivec3& res, const glm::ivec3& coarse,
                                          bool regular) const {
    K k(kernel_);
    thread_local std::vector<float> buffer;
    buffer.resize(static_cast<std::size_t>(res.x));
    float* __restrict out = buffer.data();
    float* x = texels<float>(k.u_x);
    const float* __restrict b = texels<float>(k.u_b);
    const std::uint8_t* __restrict mask = texels<std::uint8_t>(k.u_mask);
    const std::size_t plane = k.u_faces.plane;
    const float* __restrict fx = texels<float>(k.u_faces);
    const float* __restrict fy_ = fx + plane;
    const float* __restrict fz_ = fx + 2 * plane;
    const int sy = res.x, sz = res.x * res.y;
    const int fy = res.x + 1, fz = (res.x + 1) * (res.y + 1);
    const int row = y * sy + z * sz, frow = y * fy + z * fz;
    const int colour = (y + z + k.u_colour) & 1;  // cells with (i + colour) even are this sweep's
    const float* __restrict xr = x;
    // A regular row: its inner cells with the mask and fractions as constants, its end cells as any.
    const glm::vec3 open(1.0f);
    if constexpr (!kProlong) {
      auto general = [&](int i) {
        const int c = row + i, f = frow + i;
        return k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]), glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                               glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]), glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]),
                               b[c]);
      };
      if (regular) {
#pragma omp simd
        for (int i = 1; i < res.x - 1; ++i) {
          const int c = row + i;
          const float v = k.smoothedValue(kAllLinks, open, open, glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]),
                                          glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]), b[c]);
          out[i] = ((i + colour) & 1) == 0 ? v : xr[c];
        }
        for (int i : {0, res.x - 1}) out[i] = ((i + colour) & 1) == 0 ? general(i) : xr[row + i];
      } else {
#pragma omp simd
        for (int i = 0; i < res.x; ++i) {
          const int c = row + i, f = frow + i;
          const float v = k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]),
                                          glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                                          glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]),
                                          glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]), b[c]);
          out[i] = ((i + colour) & 1) == 0 ? v : xr[c];
        }
      }
    } else {
      // x + the coarse level's x of the neighbour's parent: mg_prolong folded into the sweep. The
      // parents' values are first spread to fine resolution along the row (d[1 + i] for cell i of
      // row r, i = -1 .. res.x), so the main loop's loads are contiguous.
      const float* cx = texels<float>(k.u_coarse_x);
      const int csy = coarse.x, csz = coarse.x * coarse.y;
      const int rows[5] = {(y / 2) * csy + (z / 2) * csz, ((y - 1) / 2) * csy + (z / 2) * csz,
                           ((y + 1) / 2) * csy + (z / 2) * csz, (y / 2) * csy + ((z - 1) / 2) * csz,
                           (y / 2) * csy + ((z + 1) / 2) * csz};  // this row, y-1, y+1, z-1, z+1
      // (Written in pairs, each parent twice: an element loop with i / 2 cost more than the sweep.)
      thread_local std::vector<float> spread;
      const int width = res.x + 3;  // cells -1 .. res.x, and one spare for the last pair
      spread.resize(static_cast<std::size_t>(5 * width));
      for (int r = 0; r < 5; ++r) {
        float* __restrict d = spread.data() + r * width;  // d[1 + i]: the parent of cell i
        const float* __restrict parents = cx + rows[r];
        d[0] = parents[0];  // cell -1's, as (-1) / 2 = 0
        for (int j = 0; j <= res.x / 2; ++j) {  // cells 2j and 2j + 1
          d[1 + 2 * j] = parents[j];
          d[2 + 2 * j] = parents[j];
        }
      }
      const float* __restrict mid = spread.data() + 1;
      const float* __restrict ylo = mid + width;
      const float* __restrict yhi = mid + 2 * width;
      const float* __restrict zlo = mid + 3 * width;
      const float* __restrict zhi = mid + 4 * width;
      auto general = [&](int i) {
        const int c = row + i, f = frow + i;
        return k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]), glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                               glm::vec3(xr[c - 1] + mid[i - 1], xr[c - sy] + ylo[i], xr[c - sz] + zlo[i]),
                               glm::vec3(xr[c + 1] + mid[i + 1], xr[c + sy] + yhi[i], xr[c + sz] + zhi[i]), b[c]);
      };
      if (regular) {
#pragma omp simd
        for (int i = 1; i < res.x - 1; ++i) {
          const int c = row + i;
          const float v = k.smoothedValue(kAllLinks, open, open,
                                          glm::vec3(xr[c - 1] + mid[i - 1], xr[c - sy] + ylo[i], xr[c - sz] + zlo[i]),
                                          glm::vec3(xr[c + 1] + mid[i + 1], xr[c + sy] + yhi[i], xr[c + sz] + zhi[i]),
                                          b[c]);
          out[i] = ((i + colour) & 1) == 0 ? v : xr[c];
        }
        for (int i : {0, res.x - 1}) out[i] = ((i + colour) & 1) == 0 ? general(i) : xr[row + i];
      } else {
#pragma omp simd
        for (int i = 0; i < res.x; ++i) {
          const int c = row + i, f = frow + i;
          const float v = k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]),
                                          glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                                          glm::vec3(xr[c - 1] + mid[i - 1], xr[c - sy] + ylo[i], xr[c - sz] + zlo[i]),
                                          glm::vec3(xr[c + 1] + mid[i + 1], xr[c + sy] + yhi[i], xr[c + sz] + zhi[i]),
                                          b[c]);
          out[i] = ((i + colour) & 1) == 0 ? v : xr[c];
        }
      }
    }
    std::memcpy(x + row, out, sizeof(float) * static_cast<std::size_t>(res.x));
  }

  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace

void addMgSmooth(KernelRegistry& r) {
  r.add<SmoothRows<MgSmooth, false>>("mg_smooth.comp", {});
  r.add<SmoothRows<MgSmoothProlong, true>>("mg_smooth.comp", {{"PROLONG", "1"}});
}

}  // namespace hf::cpu::kernels
