// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One row of cells of the pressure operator (common.glsl's operatorAt and residualAt) as arrays,
// for the row loops of the stages that call them (mg_residual_restrict, pcg_init, pcg_apply): a
// cell's mask, its six faces' open fractions (an RGBA32F texture keeps its channels as planes)
// and its neighbours' values are loaded by index, so a loop over the row vectorizes. A load one
// cell past the grid lands in the texture's guard band (cpu/cpu_device.cpp) and is not used:
// the cell has no link there, and operatorAt reads only linked neighbours' values.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/error.h"
#include "cpu/glsl.h"
#include "cpu/kernel.h"
#include "cpu/regular_rows.h"

namespace hf::cpu::kernels {

// Throws hf::Error naming the stage and the image when `image` is not bound at `want` texels.
inline void checkBound(const ImageBinding& image, const glm::ivec3& want, const char* stage, const char* name) {
  if (image.data == nullptr || image.size != want) {
    throw Error(std::string(stage) + ": image " + name + " is not bound at the grid's size");
  }
}

// Adds a row's terms t[0 .. n - 1] (one component) into common.glsl's ROW_PARTS parts: part l takes
// t[l], t[l + P], ... in order, as the shaders' `parts[i % ROW_PARTS] +=`. A block of P cells is
// one vector add (per part, the same adds in the same order).
template <int P>
__attribute__((always_inline)) inline void addRowParts(const float* __restrict t, int n, float (&parts)[P]) {
  int i0 = 0;
  for (; i0 + P <= n; i0 += P) {
    for (int l = 0; l < P; ++l) parts[l] += t[i0 + l];
  }
  for (int l = 0; i0 + l < n; ++l) parts[l] += t[i0 + l];
}

// The first cell of row (y, z) in a texture of a grid of `res` cells.
inline int rowStart(const glm::ivec3& res, int y, int z) { return res.x * (y + res.y * z); }

// A row's total as the row stages sum it (common.glsl: ROW_PARTS parts, then rowPartsTotal):
// component c from the row's n terms at rows + c n (addRowParts); the components after C are 0.
template <int C, class K>
__attribute__((always_inline)) inline glm::vec4 rowPartsOf(K& k, const float* rows, int n) {
  static_assert(C >= 1 && C <= 4);
  constexpr int kParts = K::ROW_PARTS;
  float sums[4][kParts] = {};
  for (int c = 0; c < C; ++c) addRowParts(rows + c * n, n, sums[c]);
  glm::vec4 parts[kParts];
  for (int l = 0; l < kParts; ++l) parts[l] = glm::vec4(sums[0][l], sums[1][l], sums[2][l], sums[3][l]);
  return k.rowPartsTotal(parts);
}

// C rows of n terms each, for a row loop to write its cells' terms into (component c at + c n)
// before rowPartsOf sums them: one buffer a thread, reused row after row.
template <int C>
inline float* termRows(int n) {
  thread_local std::vector<float> buffer;
  buffer.resize(static_cast<std::size_t>(C) * static_cast<std::size_t>(n));
  return buffer.data();
}

class PressureRow {
 public:
  // Row (y, z) of a grid of `res` cells: its mask, face fractions (res + 1 texels) and values x.
  PressureRow(const ImageBinding& mask, const ImageBinding& faces, const ImageBinding& x, const glm::ivec3& res, int y,
              int z)
      : mask_(static_cast<const std::uint8_t*>(mask.data)),
        fx_(static_cast<const float*>(faces.data)),
        fy_(fx_ + faces.plane),
        fz_(fx_ + 2 * faces.plane),
        x_(static_cast<const float*>(x.data)),
        sy_(res.x),
        sz_(res.x * res.y),
        fsy_(res.x + 1),
        fsz_((res.x + 1) * (res.y + 1)),
        cell_(y * sy_ + z * sz_),
        face_(y * fsy_ + z * fsz_) {}

  // The index of the row's cell i in a texture of the grid's size.
  int cell(int i) const { return cell_ + i; }
  float x(int i) const { return x_[cell_ + i]; }
  std::uint32_t mask(int i) const { return mask_[cell_ + i]; }
  glm::vec3 facesLo(int i) const {
    const int f = face_ + i;
    return glm::vec3(fx_[f], fy_[f], fz_[f]);
  }
  glm::vec3 facesHi(int i) const {
    const int f = face_ + i;
    return glm::vec3(fx_[f + 1], fy_[f + fsy_], fz_[f + fsz_]);
  }
  // End cell i's mask and fractions: constants where the row's `flags` (RegularRows) allow them
  // (wallLinks), else loaded.
  struct Links {
    std::uint32_t mask;
    glm::vec3 lo, hi;
  };
  Links endLinks(int i, std::uint8_t flags, int nx) const {
    const std::uint32_t wall = wallLinks(flags, i, nx);
    if (wall != 0u) return {wall, glm::vec3(1.0f), glm::vec3(1.0f)};
    return {mask(i), facesLo(i), facesHi(i)};
  }
  glm::vec3 xLo(int i) const {
    const int c = cell_ + i;
    return glm::vec3(x_[c - 1], x_[c - sy_], x_[c - sz_]);
  }
  glm::vec3 xHi(int i) const {
    const int c = cell_ + i;
    return glm::vec3(x_[c + 1], x_[c + sy_], x_[c + sz_]);
  }

 private:
  const std::uint8_t* __restrict mask_;
  const float* __restrict fx_;
  const float* __restrict fy_;
  const float* __restrict fz_;
  const float* __restrict x_;
  int sy_, sz_, fsy_, fsz_, cell_, face_;
};

// The runner of a row stage with a row loop of its own over PressureRow (pcg_apply, pcg_init: one
// invocation per row of the grid u_res): Rows::check(kernel, res) tests the bindings
// (checkBound), then Rows::row(k, y, z, res, flags) runs for every row on a per-thread copy k of
// the unchecked build K, on every thread (the serial threshold counts the row's cells, as
// RowLoopRunner's) with the best instruction set; `flags`: the row's (cpu/regular_rows.h, of the
// kernel's u_nbmask and u_face_open).
template <class K, class Rows>
class PressureRowRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 res = kernel_.u_res;
    Rows::check(kernel_, res);
    const std::uint8_t* open = bindings.regular_rows->flags(kernel_.u_nbmask, kernel_.u_face_open, res, pool, bindings.x86_v3);
    forEachRow(
        glm::ivec3(1, res.y, res.z), pool, bindings.x86_v3, kernel_,
        [&](K& k, int y, int z, int, int) { Rows::row(k, y, z, res, open[y + z * res.y]); }, res.x);
  }

 private:
  KernelSlots slots_;
  K kernel_{&slots_};
};

// The runner of a row stage whose cells are independent (pcg_dot, pcg_update, pcg_predict,
// pressure_sum: one invocation per row of the grid u_res, no neighbours): Rows::check(kernel,
// res) tests the bindings (checkBound), then Rows::row(k, y, z, res) runs for every row on a
// per-thread copy k of the unchecked build K, on every thread (the serial threshold counts the
// row's cells) with the best instruction set.
template <class K, class Rows>
class CellRowRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 res = kernel_.u_res;
    Rows::check(kernel_, res);
    forEachRow(
        glm::ivec3(1, res.y, res.z), pool, bindings.x86_v3, kernel_,
        [&](K& k, int y, int z, int, int) { Rows::row(k, y, z, res); }, res.x);
  }

 private:
  KernelSlots slots_;
  K kernel_{&slots_};
};

}  // namespace hf::cpu::kernels
