// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A MeshSource on the GPU: each step its coverage of every cell (0..1, the fraction of the cell
// inside the posed mesh), then the emission into smoke and heat, in four stages:
//   voxelize_mesh_transform  local vertices -> grid units (obstacle::PosedMesh, as MeshProbe)
//   emit_mesh_crossings      each triangle visits the sub-columns under it (kSourceSubsamples^2
//                            per cell, at (i + (a + 1/2)/S, j + (b + 1/2)/S)) and adds, in the
//                            cell holding the hit, its signed crossing and the signed length
//                            of that cell above the hit (fixed point)
//   emit_mesh_coverage       each column sums the crossings bottom-up: the winding number's
//                            integral over the cell / S^2 = the coverage (exact along z)
//   emit_coverage            smoke and heat in the source's cells, by SourceEmission x coverage
// The winding number integrates to the covered volume for any closed mesh whose shells do not
// overlap (an inside-out mesh counts as its mirror image); where shells overlap the coverage
// is clamped to 1 and partly covered overlap cells can read high. Sampling x and y on S^2
// sub-columns and integrating z exactly makes the coverage, and the emitted smoke, change in
// steps of at most 1/S of a cell's face per sub-column as the source moves, not cell by cell.
// The mesh is uploaded once per setSource() with a new mesh; a new pose uploads nothing.
#include <memory>

#include "emitter/mesh_source.h"
#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "compute/storage_buffer.h"
#include "compute/texture3d.h"
#include "obstacle/obstacle.h"
#include "obstacle/posed_mesh.h"

namespace hf::emitter {

class MeshEmitter {
 public:
  explicit MeshEmitter(const fluid::Grid& grid);
  // Takes the source's pose and values; uploads its mesh if it is not the one on the GPU
  // (compared by pointer). The source must come from makeMeshSource().
  void setSource(const MeshSource& source);
  // Writes the coverage of every cell into coverage() (R32F, 0..1).
  void voxelize();
  // Raises or adds smoke and heat in the source's cells (not in cells with no open face:
  // fluid::NB_SOLID in `nbmask`), dt_s for SourceEmission::Rate.
  void emit(compute::Texture3D& density, compute::Texture3D& temperature, const compute::Texture3D& nbmask, float dt_s);
  const compute::Texture3D& coverage() const { return coverage_; }
  // Cells the posed source can cover (its conservative world box, padded by a cell, clamped).
  obstacle::CellBox bounds() const;

 private:
  fluid::Grid grid_;
  int subcell_ = 2 * kSourceSubsamples;  // fixed-point lattice steps per cell (a multiple of 2 S)
  MeshSource source_;
  std::shared_ptr<const obstacle::TriangleMesh> uploaded_;
  obstacle::PosedMesh gpu_mesh_;
  compute::StorageBuffer crossings_;  // per cell: signed crossing count, signed fixed-point length
  compute::Texture3D coverage_;
  compute::ComputeProgram crossings_program_, coverage_program_, emit_;
};

}  // namespace hf::emitter
