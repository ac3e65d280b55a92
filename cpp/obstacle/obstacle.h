// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A solid body in the grid. Each step it writes which cells it covers (R8UI solid mask) and the
// rigid velocity at their centres (RGBA32F, m/s); the fluid reads those without knowing the
// shape: SphereProbe and MeshProbe implement it. A step may ask for a region only (the cells its
// move can change, StepPipeline): the body must bring at least those cells up to date.
#include <glm/glm.hpp>

#include "compute/texture3d.h"
#include "fluid/cell_box.h"

namespace hf::obstacle {

// Cut cells: computed open fractions below this go to 0 (continuously, common.glsl's cutOffOpen),
// so no pressure row is nearly singular.
inline constexpr float kMinOpenFraction = 0.01f;

// The box arithmetic lives with the fluid (fluid/cell_box.h); the obstacle code names it here.
using fluid::CellBox;
using fluid::faceBox;
using fluid::grownBox;
using fluid::isEmpty;
using fluid::paddedCellBox;
using fluid::unionBox;
using fluid::wholeGrid;

class Obstacle {
 public:
  virtual ~Obstacle() = default;
  // Writes the solid mask and the rigid velocity of at least the cells of `region` (the velocity
  // is read only beside faces the body covers, which lie in its bounds()).
  virtual void voxelize(compute::Texture3D& solid, compute::Texture3D& solid_velocity, const CellBox& region) = 0;
  // Cut cells: writes the open fraction of the MAC faces from the body's geometry into
  // `face_open` (shaders/common.glsl), at least those of the cells of `region` (faceBox), and
  // returns true; false (the default) when the body has no cut cells, and the faces are then
  // open or covered by its voxels (Classifier::binaryFractions).
  virtual bool writeFaceFractions(compute::Texture3D& face_open, const CellBox& region) {
    (void)face_open;
    (void)region;
    return false;
  }
  // Cells that can hold its boundary cells (the force reduction visits only these).
  virtual CellBox bounds() const = 0;
  // A world point near the body (m): the force stage sums torques about it (float precision).
  virtual glm::vec3 referencePointM() const = 0;
};

}  // namespace hf::obstacle
