// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Boxes of grid cells: the region a step's obstacle stages bring up to date (StepPipeline's
// changedRegion, obstacle/) and the coarse multigrid levels rebuild (fluid/multigrid_vcycle.h).
#include <glm/glm.hpp>

namespace hf::fluid {

struct CellBox {
  glm::ivec3 origin{0};  // first cell
  glm::ivec3 extent{0};  // cells per axis; empty when any is 0
};

// The cells of a grid-unit box [lo, hi] padded by one cell, clamped to a grid of `res` cells
// (clamped as floats first, so a box far outside cannot overflow the conversion).
inline CellBox paddedCellBox(const glm::ivec3& res, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 r(res);
  const glm::ivec3 first(glm::clamp(glm::floor(lo) - 1.0f, glm::vec3(0.0f), r));
  const glm::ivec3 end(glm::clamp(glm::ceil(hi) + 1.0f, glm::vec3(0.0f), r));
  return {first, glm::max(end - first, glm::ivec3(0))};
}

inline bool isEmpty(const CellBox& b) { return glm::any(glm::lessThanEqual(b.extent, glm::ivec3(0))); }

// Every cell of a grid of `res` cells.
inline CellBox wholeGrid(const glm::ivec3& res) { return {glm::ivec3(0), res}; }

// The smallest box holding both (an empty box adds nothing).
inline CellBox unionBox(const CellBox& a, const CellBox& b) {
  if (isEmpty(a)) return b;
  if (isEmpty(b)) return a;
  const glm::ivec3 first = glm::min(a.origin, b.origin);
  const glm::ivec3 end = glm::max(a.origin + a.extent, b.origin + b.extent);
  return {first, end - first};
}

// `b` grown by `cells` on every side, clamped to a grid of `res` cells (empty stays empty).
inline CellBox grownBox(const CellBox& b, int cells, const glm::ivec3& res) {
  if (isEmpty(b)) return b;
  const glm::ivec3 first = glm::max(b.origin - cells, glm::ivec3(0));
  const glm::ivec3 end = glm::min(b.origin + b.extent + cells, res);
  return {first, glm::max(end - first, glm::ivec3(0))};
}

// The face texels (common.glsl's face-fraction image, res + 1 per axis) of a box of cells: its
// cells' low faces and, one texel further on each axis, their high faces.
inline CellBox faceBox(const CellBox& cells, const glm::ivec3& res) {
  if (isEmpty(cells)) return cells;
  return {cells.origin, glm::min(cells.extent + 1, res + 1 - cells.origin)};
}

}  // namespace hf::fluid
