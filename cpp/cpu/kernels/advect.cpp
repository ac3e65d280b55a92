// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/advect.comp built as C++ (cpu/kernel.h).
// Every access is in range by the shader's own construction (its lookups are clamped to the
// field), so it runs unchecked, with a row loop of its own: advection is the largest stage of a
// CPU step. Where this differs from the shader, and why: the shader looks up each corner of its
// four trilinear lookups (three velocity components at the back-trace's midpoint, the field at
// its foot) on its own, which on a CPU is a gather of eight scattered loads per lookup and lane.
// Here (the AVX2 build) the row runs in blocks of kLanes texels and, per lookup, a block whose
// lanes' lower corners all lie at one of two columns past the lane's own, one of two rows and
// one of two slices (a displacement varying by under a cell across the block: 98 % of the seed
// grid's lookups) reads a window of 3 x 3 rows of kLanes + 2 texels as contiguous runs and picks
// each lane's corners from them: with one row and slice for every lane (the usual case) 2 x 2
// rows and the shader's trilinearBlend; else its lerps, x, then y, then z, each between the two
// corners picked from three. The shader's own pieces do the rest (trilinearCorner,
// trilinearFraction of common.glsl; traceMid, traceFootFrom, finishedValues of advect.comp), so
// the result is the shader's to the bit (tests/cpp/test_session_backends.cpp: the baseline build,
// which looks up every texel as the shader does, and the AVX2 build give the same bits). A block
// that strays further, or one whose corners' "+ 1" would be clamped at the field's far edge, and
// the row's last texels call the shader's lookup itself. Seed grid, 2 threads: advect 21.7-22.0
// ms against 29.9-30.0 with the lookup per texel. (Until the window was allowed to load a texel
// before the row and a column, row and slice past it, in the guard band, a row's first and last
// blocks mostly fell back: 28 % of 48^3's lookups; 3 % since, with the far column's clamp taken
// as the lookup takes it.)
#include "cpu/kernels/kernel_list.h"

#include <algorithm>
#include <climits>
#include <type_traits>

#include "common/error.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

#define FIELD_AT 0
struct AdvectUUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

// The u pass's back-trace midpoint for texels whose cross means' clamp (clampCell) changes
// nothing: x from 1 to res.x - 1. Its loads are then contiguous; with the clamp per lane they were
// gathers (the u pass cost 37 % more than v's or w's, whose clamps act on the row's y or z).
#define FIELD_AT 0
#define HF_CLAMP_FREE 1
struct AdvectUInterior : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef HF_CLAMP_FREE
#undef FIELD_AT

#define FIELD_AT 1
struct AdvectVUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 2
struct AdvectWUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
struct AdvectScalarUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT

#define FIELD_AT 3
#define PAIR 1
struct AdvectPairUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "advect.comp"
};
#undef FIELD_AT
#undef PAIR

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

// Three coordinates per lane of a block.
template <int kLanes>
struct LaneVec3 {
  float x[kLanes], y[kLanes], z[kLanes];
};

// KI: the same stage built with HF_CLAMP_FREE, whose traceMid the blocks use where their texels'
// cross means read only cells inside the grid (kInteriorX: from x = 1 to u_res.x - 1); K itself
// where the stage has no such build.
template <class K, bool kPair, class KI = K>
class AdvectRows final : public CpuKernel {
  static constexpr bool kInteriorX = !std::is_same_v<K, KI>;

 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 size = glm::min(n, kernel_.u_field_size);
    if (kernel_.u_dst.size != kernel_.u_field_size) throw Error("advect: the output is not bound at the field's size");
    forRows(
        size, pool,
        [&](int y, int z) {
          if (bindings.x86_v3)
            runBest(true, [&] { row<true>(y, z, size.x); });
          else
            runBest(false, [&] { row<false>(y, z, size.x); });
        },
        [](int, int) {});
  }

 private:
  static constexpr int kLanes = 8;  // a block: one AVX2 vector of floats
  using Lanes = LaneVec3<kLanes>;

  // kBlocks: by blocks (the AVX2 build; GCC 12 vectorizes the window's selects only there).
  template <bool kBlocks>
  __attribute__((always_inline)) void row(int y, int z, int width) const {
    K k(kernel_);
    float* __restrict out = static_cast<float*>(k.u_dst.data) + k.u_dst.index(glm::ivec3(0, y, z));
    float* __restrict out2 = nullptr;
    if constexpr (kPair) out2 = static_cast<float*>(k.u_dst2.data) + k.u_dst2.index(glm::ivec3(0, y, z));
    int x = 0;
    if constexpr (kBlocks) {
      if constexpr (kInteriorX) {
        KI ki(interior_);
        for (; x + kLanes <= width; x += kLanes) {
          if (x >= 1 && x + kLanes - 1 <= k.u_res.x - 1) {
            block(k, ki, x, y, z, out, out2);
          } else {
            block(k, k, x, y, z, out, out2);
          }
        }
      } else {
        for (; x + kLanes <= width; x += kLanes) block(k, k, x, y, z, out, out2);
      }
    }
#pragma omp simd
    for (int xt = x; xt < width; ++xt) {
      const glm::vec2 v = k.advectedValues(glm::ivec3(xt, y, z));
      out[xt] = v.x;
      if constexpr (kPair) out2[xt] = v.y;
    }
  }

  // Texels x0 .. x0 + kLanes - 1 of row (y, z): advectedValues, with the lookups by window; the
  // back-trace's midpoint by `mid_kernel` (k, or KI where its clamps change nothing).
  template <class KM>
  __attribute__((always_inline)) static void block(K& k, KM& mid_kernel, int x0, int y, int z, float* __restrict out,
                                                   float* __restrict out2) {
    Lanes mid;
    for (int l = 0; l < kLanes; ++l) {
      const glm::vec3 m = mid_kernel.traceMid(glm::ivec3(x0 + l, y, z));
      mid.x[l] = m.x;
      mid.y[l] = m.y;
      mid.z[l] = m.z;
    }
    float vx[kLanes], vy[kLanes], vz[kLanes];
    sample(k, k.u_vel_x, k.faceSize(0), mid, k.faceOffset(0), vx,
           [&](const glm::vec3& t) __attribute__((always_inline)) { return k.sampleVx(k.faceSize(0), t); });
    sample(k, k.u_vel_y, k.faceSize(1), mid, k.faceOffset(1), vy,
           [&](const glm::vec3& t) __attribute__((always_inline)) { return k.sampleVy(k.faceSize(1), t); });
    sample(k, k.u_vel_z, k.faceSize(2), mid, k.faceOffset(2), vz,
           [&](const glm::vec3& t) __attribute__((always_inline)) { return k.sampleVz(k.faceSize(2), t); });
    Lanes foot;
    for (int l = 0; l < kLanes; ++l) {
      const glm::vec3 t = k.traceFootFrom(glm::ivec3(x0 + l, y, z), glm::vec3(vx[l], vy[l], vz[l]));
      foot.x[l] = t.x;
      foot.y[l] = t.y;
      foot.z[l] = t.z;
    }
    float s[kLanes], s2[kLanes] = {};
    sample(k, k.u_src, k.u_field_size, foot, glm::vec3(0.0f), s,
           [&](const glm::vec3& t) __attribute__((always_inline)) { return k.sampleSrc(k.u_field_size, t); });
    if constexpr (kPair)
      sample(k, k.u_src2, k.u_field_size, foot, glm::vec3(0.0f), s2,
             [&](const glm::vec3& t) __attribute__((always_inline)) { return k.sampleSrc2(k.u_field_size, t); });
    for (int l = 0; l < kLanes; ++l) {
      const glm::vec2 v = k.finishedValues(glm::ivec3(x0 + l, y, z), glm::vec2(s[l], s2[l]));
      out[x0 + l] = v.x;
      if constexpr (kPair) out2[x0 + l] = v.y;
    }
  }

  // The 2 x 2 rows' lookups (rows[slice][row] from column x_lo): lane l's corners at column
  // x_lo + l or one past it (cx: the corner's column less l), trilinearBlend as the shader's.
  // kFarColumn: a lane whose corner is the last column (size_x - 1) takes its "+ 1" as the corner
  // itself, as the lookup's clamp does (the same operands).
  template <bool kFarColumn>
  __attribute__((always_inline)) static void blendRows(K& k, const float* const (&rows)[3][3], const int* cx,
                                                       const float* fx, const float* fy, const float* fz, int x_lo,
                                                       int size_x, float* __restrict result) {
    for (int l = 0; l < kLanes; ++l) {
      const bool up_x = cx[l] != x_lo;
      const bool last = kFarColumn && cx[l] + l == size_x - 1;
      auto corners = [&](const float* r, float& c0, float& c1) __attribute__((always_inline)) {
        const float r0 = r[l], r1 = r[l + 1], r2 = r[l + 2];  // loaded always: no branch around a load
        c0 = up_x ? r1 : r0;
        c1 = up_x ? r2 : r1;
        if constexpr (kFarColumn) c1 = last ? c0 : c1;
      };
      float c000, c100, c010, c110, c001, c101, c011, c111;
      corners(rows[0][0], c000, c100);
      corners(rows[0][1], c010, c110);
      corners(rows[1][0], c001, c101);
      corners(rows[1][1], c011, c111);
      result[l] = k.trilinearBlend(c000, c100, c010, c110, c001, c101, c011, c111, glm::vec3(fx[l], fy[l], fz[l]));
    }
  }

  // result[l] = the trilinear lookup of `image` (`size` texels) at p[l] - offset (the shader's
  // NAME(size, p - offset) of DEFINE_TRILINEAR, which `lookup` is).
  template <class Image, class Lookup>
  __attribute__((always_inline)) static void sample(K& k, const Image& image, const glm::ivec3& size,
                                                    const Lanes& p, const glm::vec3& offset, float* __restrict result,
                                                    const Lookup& lookup) {
    int cx[kLanes], cy[kLanes], cz[kLanes];  // the lower corner, x relative to the lane
    float fx[kLanes], fy[kLanes], fz[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      const glm::vec3 t = glm::vec3(p.x[l], p.y[l], p.z[l]) - offset;
      const glm::ivec3 c = k.trilinearCorner(size, t);
      const glm::vec3 f = k.trilinearFraction(size, t);
      cx[l] = c.x - l;
      cy[l] = c.y;
      cz[l] = c.z;
      fx[l] = f.x;
      fy[l] = f.y;
      fz[l] = f.z;
    }
    // The window: columns x_lo + l .. x_lo + l + 2 of lane l, rows y_lo .. y_lo + 2, slices
    // z_lo .. z_lo + 2, when every lane's corner is at the lowest or one past it and every corner's
    // "+ 1" is inside the image (unclamped, as the lookup takes it). The window's loads may reach
    // one texel before the image (column -1 for lane 0, whose corner is then x_lo + 1: it is never
    // used) and a column, a row and a slice past its corners' (loaded always, used by no lane):
    // they land in the texture's guard band of a slice, a row and a texel (cpu_device.cpp) or in
    // the image's next row or slice, memory the texture owns.
    int x_lo = INT_MAX, x_hi = INT_MIN, y_lo = INT_MAX, y_hi = INT_MIN, z_lo = INT_MAX, z_hi = INT_MIN;
    int x_top = INT_MIN;  // the largest corner column
#pragma omp simd reduction(min : x_lo, y_lo, z_lo) reduction(max : x_hi, y_hi, z_hi, x_top)
    for (int l = 0; l < kLanes; ++l) {
      x_lo = std::min(x_lo, cx[l]);
      x_hi = std::max(x_hi, cx[l]);
      x_top = std::max(x_top, cx[l] + l);
      y_lo = std::min(y_lo, cy[l]);
      y_hi = std::max(y_hi, cy[l]);
      z_lo = std::min(z_lo, cz[l]);
      z_hi = std::max(z_hi, cz[l]);
    }
    const bool near = x_hi - x_lo <= 1 && y_hi - y_lo <= 1 && z_hi - z_lo <= 1 && x_lo >= -1 &&
                      y_hi + 1 <= size.y - 1 && z_hi + 1 <= size.z - 1;
    const bool inside = x_top + 1 <= size.x - 1;
    // A block at the row's far end whose last corner is the far column (its "+ 1" clamps to it),
    // with one row and slice for every lane: the 2 x 2 rows below, that corner's "+ 1" taken as
    // itself as the lookup takes it. Its loads reach two texels past the row: the next row's, or
    // the guard band after the last.
    const bool far_column = x_top == size.x - 1 && y_hi == y_lo && z_hi == z_lo;
    if (!near || !(inside || far_column)) {
      for (int l = 0; l < kLanes; ++l) result[l] = lookup(glm::vec3(p.x[l], p.y[l], p.z[l]) - offset);
      return;
    }
    const float* rows[3][3];  // [slice][row]
    for (int dz = 0; dz < 3; ++dz)
      for (int dy = 0; dy < 3; ++dy)
        rows[dz][dy] = static_cast<const float*>(image.data) + image.index(glm::ivec3(x_lo, y_lo + dy, z_lo + dz));
    if (y_hi == y_lo && z_hi == z_lo) {  // one row and slice for every lane (the usual case): 2 x 2 rows
      if (inside) {
        blendRows<false>(k, rows, cx, fx, fy, fz, x_lo, size.x, result);
      } else {
        blendRows<true>(k, rows, cx, fx, fy, fz, x_lo, size.x, result);
      }
      return;
    }
    for (int l = 0; l < kLanes; ++l) {
      const bool up_x = cx[l] != x_lo, up_y = cy[l] != y_lo, up_z = cz[l] != z_lo;
      const float f_x = fx[l], f_y = fy[l], f_z = fz[l];
      // trilinearBlend's lerps, x, then y, then z, each between the lane's two corners picked
      // from the three the window holds on that axis: the same operations on the same values.
      auto along_x = [&](const float* r) __attribute__((always_inline)) {
        const float r0 = r[l], r1 = r[l + 1], r2 = r[l + 2];  // loaded always: no branch around a load
        return glm::mix(up_x ? r1 : r0, up_x ? r2 : r1, f_x);
      };
      auto along_y = [&](int slice) __attribute__((always_inline)) {
        const float a0 = along_x(rows[slice][0]), a1 = along_x(rows[slice][1]), a2 = along_x(rows[slice][2]);
        return glm::mix(up_y ? a1 : a0, up_y ? a2 : a1, f_y);
      };
      const float s0 = along_y(0), s1 = along_y(1), s2 = along_y(2);
      result[l] = glm::mix(up_z ? s1 : s0, up_z ? s2 : s1, f_z);
    }
  }

  struct NoInterior {
    explicit NoInterior(KernelSlots*) {}
  };
  KernelSlots slots_;  // both builds register here: bindings and uniforms reach both
  K kernel_{&slots_};
  std::conditional_t<kInteriorX, KI, NoInterior> interior_{&slots_};
};

}  // namespace

void addAdvect(KernelRegistry& r) {
  r.add<AdvectRows<AdvectUUnchecked, false, AdvectUInterior>>("advect.comp", {{"FIELD_AT", "0"}});
  r.add<AdvectRows<AdvectVUnchecked, false>>("advect.comp", {{"FIELD_AT", "1"}});
  r.add<AdvectRows<AdvectWUnchecked, false>>("advect.comp", {{"FIELD_AT", "2"}});
  r.add<AdvectRows<AdvectScalarUnchecked, false>>("advect.comp", {{"FIELD_AT", "3"}});
  r.add<AdvectRows<AdvectPairUnchecked, true>>("advect.comp", {{"FIELD_AT", "3"}, {"PAIR", "1"}});
}

}  // namespace hf::cpu::kernels
