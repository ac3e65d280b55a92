#pragma once
// A rigid closed triangle mesh voxelized on the GPU every step by ray parity along z
// (see triangle_mesh.h for the rule), in three stages:
//   voxelize_mesh_transform  local vertices -> grid units (the pose's matrix)
//   voxelize_mesh_crossings  each triangle visits the cell columns under it and adds its signed
//                            crossing (+1 entering, -1 leaving) at the first cell above the hit
//   voxelize_mesh_fill       each column sums its crossings bottom-up: solid where nonzero; the
//                            rigid velocity v + w x (x - origin) at solid cell centres
// Cost: O(triangles + columns under them + cells), not cells x triangles. The mesh is uploaded
// once per setMesh(); a new pose uploads nothing.
#include <memory>

#include "fluid/grid.h"
#include "gl/compute_program.h"
#include "gl/storage_buffer.h"
#include "obstacle/obstacle.h"
#include "obstacle/triangle_mesh.h"

namespace hf::obstacle {

class MeshProbe : public Obstacle {
 public:
  explicit MeshProbe(const fluid::Grid& grid);
  // Uploads the mesh if it is not the one already on the GPU (compared by pointer); the mesh
  // must have passed validateMesh().
  void setMesh(std::shared_ptr<const TriangleMesh> mesh);
  void setPose(const RigidPose& pose);
  void voxelize(gl::Texture3D& solid, gl::Texture3D& solid_velocity) override;
  CellBox bounds() const override;
  glm::vec3 referencePointM() const override;

 private:
  fluid::Grid grid_;
  int subcell_ = 2;  // fixed-point steps per cell for the exact column-in-triangle tests
  std::shared_ptr<const TriangleMesh> mesh_;
  MeshExtent extent_;
  RigidPose pose_;
  std::unique_ptr<gl::StorageBuffer> local_vertices_, grid_vertices_, indices_;
  gl::StorageBuffer crossings_;
  gl::ComputeProgram transform_, crossings_program_, fill_;
};

}  // namespace hf::obstacle
