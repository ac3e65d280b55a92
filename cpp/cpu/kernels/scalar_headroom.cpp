// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/scalar_headroom.comp built as C++ (cpu/kernel.h).
// A row stage, unchecked: its accesses are the row's cells and their six neighbours, one cell
// past the grid at most (in the texture's guard band, and not used: a neighbour across an
// unlinked face counts as the cell itself). Its own row loop, on every thread: the shader's
// headroomAt for every cell of the row, vectorized, into row buffers, then addHeadroom over them
// in the row's order, as the shader sums (the same bits; the shader's loop, one cell at a time
// with branches, ran it scalar: 2.3 % of a seed step). A row whose inner cells are all linked to
// their six neighbours (most rows) runs them with the mask a constant.
#include "cpu/kernels/kernel_list.h"

#include <cstdint>
#include <vector>

#include "common/error.h"
#include "cpu/kernels/pressure_row.h"  // checkBound
#include "cpu/regular_rows.h"         // kAllLinks, byLinkedInside

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct ScalarHeadroomUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "scalar_headroom.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

using K = ScalarHeadroomUnchecked;

class HeadroomRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 res = kernel_.u_res;
    constexpr const char* stage = "scalar_headroom";
    checkBound(kernel_.u_density, res, stage, "density");
    checkBound(kernel_.u_temperature, res, stage, "temperature");
    checkBound(kernel_.u_nbmask, res, stage, "nbmask");
    if (kernel_.partials.length() < 2 * static_cast<std::size_t>(res.y) * static_cast<std::size_t>(res.z)) {
      throw Error("scalar_headroom: the partials buffer holds fewer than two vec4s per row");
    }
    // One grid row per row of the box, as PressureRowRunner dispatches (the serial threshold
    // counts the row's cells).
    forEachRow(
        glm::ivec3(1, res.y, res.z), pool, bindings.x86_v3, kernel_,
        [&](K& k, int y, int z, int, int) { row(k, y, z, res); }, res.x);
  }

 private:
  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res) {
    thread_local std::vector<float> parts;
    parts.resize(static_cast<std::size_t>(4 * res.x));
    float* __restrict rise_d = parts.data();
    float* __restrict fall_d = rise_d + res.x;
    float* __restrict rise_t = fall_d + res.x;
    float* __restrict fall_t = rise_t + res.x;
    const int at = k.u_density.index(glm::ivec3(0, y, z));
    const float* __restrict d = static_cast<const float*>(k.u_density.data) + at;
    const float* __restrict t = static_cast<const float*>(k.u_temperature.data) + at;
    const std::uint8_t* __restrict nb = static_cast<const std::uint8_t*>(k.u_nbmask.data) + at;
    // The inner cells all linked (most rows): the mask kAllLinks as a constant, so the selects
    // fold away (the same max and min of the same values: the same bits).
    byLinkedInside(nb, 0, res.x, res.x, [&](auto linked, int b, int e) {
      cells<decltype(linked)::value>(k, y, z, b, e, d, t, nb, rise_d, fall_d, rise_t, fall_t);
    });
    glm::vec4 d_acc(0.0f), t_acc(0.0f);
    for (int i = 0; i < res.x; ++i) {
      k.addHeadroom(d_acc, t_acc, d[i], t[i], glm::vec4(rise_d[i], fall_d[i], rise_t[i], fall_t[i]));
    }
    const std::size_t rows = static_cast<std::size_t>(res.y) * static_cast<std::size_t>(res.z);
    const std::size_t slot = static_cast<std::size_t>(y + res.y * z);
    k.partials[slot] = d_acc;
    k.partials[rows + slot] = t_acc;
  }

  // Cells b .. e - 1 of row (y, z) into the row buffers: the mask kAllLinks as a constant where
  // kLinked, else loaded.
  template <bool kLinked>
  __attribute__((always_inline)) static void cells(K& k, int y, int z, int b, int e, const float* __restrict d,
                                                   const float* __restrict t, const std::uint8_t* __restrict nb,
                                                   float* __restrict rise_d, float* __restrict fall_d,
                                                   float* __restrict rise_t, float* __restrict fall_t) {
#pragma omp simd
    for (int i = b; i < e; ++i) {
      const std::uint32_t mask = kLinked ? kAllLinks : nb[i];
      const glm::vec4 room = k.headroomAt(glm::ivec3(i, y, z), mask, d[i], t[i]);
      rise_d[i] = room.x;
      fall_d[i] = room.y;
      rise_t[i] = room.z;
      fall_t[i] = room.w;
    }
  }

  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace

void addScalarHeadroom(KernelRegistry& r) { r.add<HeadroomRows>("scalar_headroom.comp", {}); }

}  // namespace hf::cpu::kernels
