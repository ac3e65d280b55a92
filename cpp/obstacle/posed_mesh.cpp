// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/posed_mesh.h"

#include <vector>

#include "compute/workgroup.h"

namespace hf::obstacle {

glm::dmat4 localToLattice(const glm::mat4& local_to_world, const glm::vec3& origin_m, double cell_m,
                          const glm::ivec3& first_cell) {
  const glm::dmat4 m(local_to_world);
  glm::dmat4 to_lattice(1.0);
  for (int c = 0; c < 3; ++c) to_lattice[c] = glm::dvec4(glm::dvec3(m[c]) / cell_m, 0.0);
  to_lattice[3] = glm::dvec4((glm::dvec3(m[3]) - glm::dvec3(origin_m)) / cell_m - glm::dvec3(first_cell), 1.0);
  return to_lattice;
}

PosedMesh::PosedMesh() : transform_("voxelize_mesh_transform.comp", compute::linearGroupDefines()) {}

void PosedMesh::upload(const TriangleMesh& mesh, const std::string& what) {
  const std::size_t nv = mesh.vertices_m.size(), nt = mesh.triangles.size();
  std::vector<glm::vec4> v(nv);
  for (std::size_t i = 0; i < nv; ++i) v[i] = glm::vec4(mesh.vertices_m[i], 1.0f);
  local_vertices_ = std::make_unique<compute::StorageBuffer>(nv * sizeof(glm::vec4), what + " vertices");
  local_vertices_->upload(v.data(), nv * sizeof(glm::vec4));
  grid_vertices_ = std::make_unique<compute::StorageBuffer>(nv * sizeof(glm::vec4), what + " vertices in grid units");
  indices_ = std::make_unique<compute::StorageBuffer>(nt * sizeof(glm::uvec3), what + " triangles");
  indices_->upload(mesh.triangles.data(), nt * sizeof(glm::uvec3));
  vertices_ = static_cast<unsigned>(nv);
  triangles_ = static_cast<unsigned>(nt);
}

void PosedMesh::pose(const glm::dmat4& local_to_lattice) {
  local_vertices_->bind(0);
  grid_vertices_->bind(1);
  transform_.set("u_to_grid", glm::mat4(local_to_lattice));
  transform_.set("u_count", vertices_);
  transform_.dispatch(glm::ivec3(static_cast<int>(vertices_), 1, 1));
}

void PosedMesh::dispatchCrossings(compute::ComputeProgram& program, compute::StorageBuffer& crossings) const {
  crossings.clear();
  grid_vertices_->bind(0);
  indices_->bind(1);
  crossings.bind(2);
  program.set("u_count", triangles_);
  program.dispatch(glm::ivec3(static_cast<int>(triangles_), 1, 1));
}

}  // namespace hf::obstacle
