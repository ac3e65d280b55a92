#pragma once
// A solid body in the grid. Each step it writes which cells it covers (R8UI solid mask) and the
// rigid velocity at their centres (RGBA32F, m/s); the fluid reads those without knowing the
// shape: SphereProbe and MeshProbe implement it.
#include <glm/glm.hpp>

#include "gl/texture3d.h"

namespace hf::obstacle {

// Cut cells: computed open fractions below this go to 0 (continuously, common.glsl's cutOffOpen),
// so no pressure row is nearly singular.
inline constexpr float kMinOpenFraction = 0.01f;

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

class Obstacle {
 public:
  virtual ~Obstacle() = default;
  virtual void voxelize(gl::Texture3D& solid, gl::Texture3D& solid_velocity) = 0;
  // Cut cells: writes the open fraction of every MAC face from the body's geometry into
  // `face_open` (shaders/common.glsl) and returns true; false (the default) when the body has no
  // cut cells, and the faces are then open or covered by its voxels (Classifier::binaryFractions).
  virtual bool writeFaceFractions(gl::Texture3D& face_open) {
    (void)face_open;
    return false;
  }
  // Cells that can hold its boundary cells (the force reduction visits only these).
  virtual CellBox bounds() const = 0;
  // A world point near the body (m): the force stage sums torques about it (float precision).
  virtual glm::vec3 referencePointM() const = 0;
};

}  // namespace hf::obstacle
