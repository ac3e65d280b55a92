// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Which rows of a pressure grid are wholly open inside: for each row (y, z), whether its cells
// 1 .. nx - 2 are all fluid with six linked neighbours (common.glsl's mask bits 0..5, no open top,
// not solid) and six face fractions of exactly 1. Most rows of a real grid are (6522 of the seed
// grid's 7000), and for them the row loops of the pressure stages (mg_smooth, mg_residual_restrict,
// pcg_apply, pcg_init) call the shader's per-cell function with kAllLinks and unit fractions as
// constants: the mask's bit tests fold away and neither mask nor faces is read, with the same bits
// (1 * v is v; the sums add the same terms in the same order). A row's first and last cell are
// flagged too where they are against a wall on x with their five other faces whole (most rows of a
// closed box): those stages then take their masks and fractions as constants as well, so a
// regular row reads no mask or fraction at all (the end cells' were cache lines of their own,
// missed once a row: 4-7 % of the seed grid's pressure solve).
//
// One per CPU device (Bindings::regular_rows), used on its thread: the flags of a (mask, faces)
// pair are derived on first use and kept while neither changes (ImageBinding::version), one set
// per multigrid level, shared by the stages that read the same level; where the textures' words
// (compute::Texture3D::changedOnlyIn) bound what changed, only those rows are derived again.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "cpu/glsl.h"
#include "cpu/kernel.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {

inline constexpr std::uint32_t kAllLinks = 0x3Fu;
// A row's first and last cell against a wall on x (the cell's -x or +x neighbour outside the grid,
// or solid): all links but that one. (The stages' per-cell functions read no unlinked face's
// fraction nor neighbour's x, so unit fractions stand for the five linked faces.)
inline constexpr std::uint32_t kWallLowLinks = kAllLinks & ~1u;
inline constexpr std::uint32_t kWallHighLinks = kAllLinks & ~2u;

// Whether cells begin .. end - 1 of a row of masks all have kAllLinks (true for none). Every cell
// is tested, no early exit, so that the loop vectorizes.
inline bool allLinked(const std::uint8_t* mask, int begin, int end) {
  unsigned other = 0u;
  for (int i = begin; i < end; ++i) other |= static_cast<unsigned>(mask[i] != kAllLinks);
  return other == 0u;
}

// Runs run(linked, b, e) over cells x0 .. x1 - 1 of a row of nx cells with masks `mask`, in order:
// where the inner cells (1 .. nx - 2) of that range all have kAllLinks, over them with `linked` a
// std::true_type and over the rest (the row's ends, which a wall may cut off) with a
// std::false_type; else over the whole range with a std::false_type. For the row loops that run
// a wholly linked run of cells with the mask a constant (scalar_correct, scalar_headroom).
template <class Run>
inline void byLinkedInside(const std::uint8_t* mask, int x0, int x1, int nx, Run&& run) {
  const int lo = std::max(x0, 1), hi = std::min(x1, nx - 1);
  if (lo >= hi || !allLinked(mask, lo, hi)) {
    run(std::false_type(), x0, x1);
    return;
  }
  run(std::false_type(), x0, lo);
  run(std::true_type(), lo, hi);
  run(std::false_type(), hi, x1);
}

// The bits of a row's flags.
inline constexpr std::uint8_t kOpenInside = 1;  // cells 1 .. nx - 2: kAllLinks, unit fractions
inline constexpr std::uint8_t kWallLow = 2;     // cell 0: kWallLowLinks, its linked faces' fractions 1
inline constexpr std::uint8_t kWallHigh = 4;    // cell nx - 1: kWallHighLinks, likewise

// The mask a row's end cell i (0 or nx - 1) takes as a constant, with unit fractions, where the
// row's flags allow it (kWallLowLinks, kWallHighLinks); 0 where its mask and fractions are loaded.
inline std::uint32_t wallLinks(std::uint8_t flags, int i, int nx) {
  if (i == 0 && (flags & kWallLow) != 0) return kWallLowLinks;
  if (i == nx - 1 && (flags & kWallHigh) != 0) return kWallHighLinks;
  return 0u;
}

class RegularRows {
 public:
  // Row flags (kOpenInside, kWallLow, kWallHigh), indexed y + z * res.y, of the grid `res` whose mask and
  // face fractions ((res + 1) texels, RGBA32F planes) are bound in `mask` and `faces`; derived
  // with the x86-64-v3 build of the loop where `x86_v3` (Bindings::x86_v3). Where both images
  // changed since the flags were last derived only where their textures' words say
  // (ImageBinding::change: the pressure solver's word for the obstacle's cells, each step), only
  // the rows those texels touch are derived again (the seed grid's flags are 0.5-0.7 ms a step).
  const std::uint8_t* flags(const ImageBinding& mask, const ImageBinding& faces, const glm::ivec3& res,
                            ThreadPool& pool, bool x86_v3) {
    for (Entry& e : entries_) {
      if (e.mask != mask.data || e.faces != faces.data || e.res != res) continue;
      if (e.mask_version == mask.version && e.faces_version == faces.version) return e.flags.data();
      Rows rows = Rows::none(res);
      if (!changedRows(mask, e.mask_version, 0, res, rows) || !changedRows(faces, e.faces_version, 1, res, rows)) {
        rows = Rows::all(res);
      }
      derive(e, mask, faces, res, rows, pool, x86_v3);
      e.mask_version = mask.version;
      e.faces_version = faces.version;
      return e.flags.data();
    }
    if (entries_.size() >= kMaxEntries) entries_.clear();
    Entry e{mask.data, mask.version, faces.data, faces.version, res, std::vector<std::uint8_t>()};
    e.flags.assign(static_cast<std::size_t>(res.y) * res.z, 0);
    derive(e, mask, faces, res, Rows::all(res), pool, x86_v3);
    entries_.push_back(std::move(e));
    return entries_.back().flags.data();
  }

 private:
  static constexpr std::size_t kMaxEntries = 16;
  // The rows (y, z) in [lo, hi) of a grid (empty where lo is not below hi on both).
  struct Rows {
    glm::ivec2 lo;
    glm::ivec2 hi;
    static Rows all(const glm::ivec3& res) { return {glm::ivec2(0), glm::ivec2(res.y, res.z)}; }
    static Rows none(const glm::ivec3& res) { return {glm::ivec2(res.y, res.z), glm::ivec2(0)}; }
    bool empty() const { return glm::any(glm::greaterThanEqual(lo, hi)); }
  };
  struct Entry {
    const void* mask;
    std::uint64_t mask_version;
    const void* faces;
    std::uint64_t faces_version;
    glm::ivec3 res;
    std::vector<std::uint8_t> flags;
  };

  // Whether `image`, derived from at version `had`, changed since only where its word says; if
  // so, grows `rows` (y and z of the grid's rows) by the rows its changed texels touch: a cell's
  // row, and for a face texel (`halo` 1) also the row below and the one behind (its y and z
  // faces are those cells' upper faces).
  static bool changedRows(const ImageBinding& image, std::uint64_t had, int halo, const glm::ivec3& res, Rows& rows) {
    if (image.version == had) return true;
    const ChangeNote* note = image.change;
    if (note == nullptr || note->from != had || note->to != image.version) return false;
    if (glm::any(glm::lessThanEqual(note->extent, glm::ivec3(0)))) return true;
    const Rows all = Rows::all(res);
    const Rows changed{glm::max(glm::ivec2(note->origin.y, note->origin.z) - halo, all.lo),
                       glm::min(glm::ivec2(note->origin.y + note->extent.y, note->origin.z + note->extent.z), all.hi)};
    if (changed.empty()) return true;
    rows = {glm::min(rows.lo, changed.lo), glm::max(rows.hi, changed.hi)};
    return true;
  }

  // The flags of `rows`.
  static void derive(Entry& e, const ImageBinding& mask, const ImageBinding& faces, const glm::ivec3& res,
                     const Rows& rows, ThreadPool& pool, bool x86_v3) {
    if (rows.empty()) return;
    const std::uint8_t* m = static_cast<const std::uint8_t*>(mask.data);
    const float* fx = static_cast<const float*>(faces.data);
    const float* fy = fx + faces.plane;
    const float* fz = fx + 2 * faces.plane;
    const int sy = res.x + 1, sz = (res.x + 1) * (res.y + 1);
    std::uint8_t* out = e.flags.data();
    forRows(
        glm::ivec3(1, rows.hi - rows.lo), pool,
        [&](int ry, int rz) {
          const int y = rows.lo.x + ry, z = rows.lo.y + rz;
          runBest(x86_v3, [&] {
            const int row = y * res.x + z * res.x * res.y, frow = y * sy + z * sz;
            // Every cell tested, no early exit, so that the loops vectorize (most rows are open):
            // the mask's bytes and the fractions' floats in loops of their own.
            unsigned closed = res.x > 2 && allLinked(m + row, 1, res.x - 1) ? 0u : 1u;
            for (int i = 1; i < res.x - 1; ++i) {
              const int f = frow + i;
              closed |= static_cast<unsigned>(fx[f] != 1.0f) | static_cast<unsigned>(fx[f + 1] != 1.0f) |
                        static_cast<unsigned>(fy[f] != 1.0f) | static_cast<unsigned>(fy[f + sy] != 1.0f) |
                        static_cast<unsigned>(fz[f] != 1.0f) | static_cast<unsigned>(fz[f + sz] != 1.0f);
            }
            // The end cells: each with its five linked faces' fractions.
            const int l = row, lf = frow, h = row + res.x - 1, hf = frow + res.x - 1;
            const bool low = m[l] == kWallLowLinks && fx[lf + 1] == 1.0f && fy[lf] == 1.0f && fy[lf + sy] == 1.0f &&
                             fz[lf] == 1.0f && fz[lf + sz] == 1.0f;
            const bool high = m[h] == kWallHighLinks && fx[hf] == 1.0f && fy[hf] == 1.0f && fy[hf + sy] == 1.0f &&
                              fz[hf] == 1.0f && fz[hf + sz] == 1.0f;
            out[y + z * res.y] = static_cast<std::uint8_t>((closed == 0 ? kOpenInside : 0) | (low ? kWallLow : 0) |
                                                           (high ? kWallHigh : 0));
          });
        },
        [](int, int) {}, res.x);
  }

  std::vector<Entry> entries_;
};

}  // namespace hf::cpu
