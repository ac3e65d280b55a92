// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A TriangleMesh on the GPU for the ray-parity stages that obstacle::MeshProbe and
// emitter::MeshEmitter share: its local vertices and triangles (uploaded once per mesh), the
// vertices posed into a grid's cell units by voxelize_mesh_transform, and the dispatch of a
// per-triangle crossings program over them.
#include <cstddef>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "compute/compute_program.h"
#include "compute/storage_buffer.h"
#include "obstacle/triangle_mesh.h"

namespace hf::obstacle {

// local -> world -> lattice units, composed in double: cell i of a lattice of `cell_m` cells
// whose cell 0 starts at `origin_m` spans [i, i+1]; `first_cell` is subtracted (a sub-lattice).
glm::dmat4 localToLattice(const glm::mat4& local_to_world, const glm::vec3& origin_m, double cell_m,
                          const glm::ivec3& first_cell = glm::ivec3(0));

class PosedMesh {
 public:
  PosedMesh();
  // Uploads the mesh (which must have passed validateMesh()); `what` names its buffers in GL errors.
  void upload(const TriangleMesh& mesh, const std::string& what);
  // Writes every vertex in lattice units (localToLattice's matrix) into the posed buffer.
  void pose(const glm::dmat4& local_to_lattice);
  // Clears `crossings`, binds the posed vertices (0), the triangles (1) and `crossings` (2), and
  // dispatches `program` once per triangle with u_count set.
  void dispatchCrossings(compute::ComputeProgram& program, compute::StorageBuffer& crossings) const;

 private:
  unsigned vertices_ = 0, triangles_ = 0;
  std::unique_ptr<compute::StorageBuffer> local_vertices_, grid_vertices_, indices_;
  compute::ComputeProgram transform_;
};

}  // namespace hf::obstacle
