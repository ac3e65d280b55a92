// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A rigid closed triangle mesh voxelized on the GPU every step by ray parity along z
// (see triangle_mesh.h for the rule), in three stages:
//   voxelize_mesh_transform  local vertices -> grid units (the pose's matrix; PosedMesh)
//   voxelize_mesh_crossings  each triangle visits the cell columns under it and adds its signed
//                            crossing (+1 entering, -1 leaving) at the first cell above the hit
//   voxelize_mesh_fill       each column sums its crossings bottom-up: solid where nonzero; the
//                            rigid velocity v + w x (x - origin) at solid cell centres
// Cost: O(triangles + columns under them + cells), not cells x triangles. The mesh is uploaded
// once per setMesh(); a new pose uploads nothing.
// Cut cells (setCutCells): writeFaceFractions voxelizes the probe's cell box again on a grid
// kFineCells times finer per axis (2 where that would exceed kMaxFineCells) with the same
// transform and crossings stages, sums each fine column in place (voxelize_mesh_winding), and
// gives every face the fluid share of the fine cells in its control volume (mesh_fractions).
#include <cstddef>
#include <memory>

#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "compute/storage_buffer.h"
#include "obstacle/obstacle.h"
#include "obstacle/posed_mesh.h"
#include "obstacle/triangle_mesh.h"

namespace hf::obstacle {

inline constexpr int kFineCells = 4;                        // fine cells per cell and axis (cut cells)
inline constexpr std::size_t kMaxFineCells = std::size_t{1} << 24;  // 64 MiB of winding numbers

class MeshProbe : public Obstacle {
 public:
  explicit MeshProbe(const fluid::Grid& grid);
  // Uploads the mesh if it is not the one already on the GPU (compared by pointer); the mesh
  // must have passed validateMesh().
  void setMesh(std::shared_ptr<const TriangleMesh> mesh);
  void setPose(const RigidPose& pose);
  // voxelize fills the region's columns whole (bottom to top: a column's winding numbers start
  // at its floor); writeFaceFractions writes the region's faces (faceBox). The crossings and the
  // fine voxelization cover the mesh wherever it is.
  void voxelize(compute::Texture3D& solid, compute::Texture3D& solid_velocity, const CellBox& region) override;
  // The faces' open fractions from the fine voxelization when cut cells are on; else false.
  bool writeFaceFractions(compute::Texture3D& face_open, const CellBox& region) override;
  void setCutCells(bool on) { cut_cells_ = on; }
  // Fine cells per cell and axis for a cell box of `box_cells` cells (even, >= 2).
  static int fineCellsFor(std::size_t box_cells);
  CellBox bounds() const override;
  glm::vec3 referencePointM() const override;

 private:
  fluid::Grid grid_;
  int subcell_ = 2;  // fixed-point steps per cell for the exact column-in-triangle tests
  std::shared_ptr<const TriangleMesh> mesh_;
  MeshExtent extent_;
  RigidPose pose_;
  PosedMesh gpu_mesh_;
  compute::StorageBuffer crossings_;
  compute::ComputeProgram crossings_program_, fill_;
  bool cut_cells_ = false;
  std::unique_ptr<compute::StorageBuffer> fine_winding_;  // grown to the largest fine grid used
  compute::ComputeProgram fine_crossings_, winding_, fractions_;
};

}  // namespace hf::obstacle
