// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Turns the solid mask into the seed's four cell classes and the pressure stages' neighbour
// mask (one GPU pass over the grid, or over the region of it a step asks for).
#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "compute/texture3d.h"
#include "obstacle/obstacle.h"

namespace hf::obstacle {

class Classifier {
 public:
  explicit Classifier(const fluid::Grid& grid);
  // Both write at least the cells of `region` (and their faces: faceBox), the only ones whose
  // inputs may have changed; the rest keep their values.
  // Face fractions of the voxels alone: a face is covered (0) when a cell beside it is solid.
  void binaryFractions(const compute::Texture3D& solid, compute::Texture3D& face_open, const CellBox& region);
  // Classes by cell centre from `solid`; the neighbour mask from the face fractions.
  void classify(const compute::Texture3D& solid, const compute::Texture3D& face_open, compute::Texture3D& cell_class,
                compute::Texture3D& nbmask, bool open_top, const CellBox& region);

 private:
  fluid::Grid grid_;
  compute::ComputeProgram program_;
  compute::ComputeProgram binary_;
};

}  // namespace hf::obstacle
