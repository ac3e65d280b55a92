// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A closed triangle mesh in its object's local frame (m) and its rigid pose in the world, with
// the host-side checks that every mesh and pose pass before the GPU sees them.
//
// Rule for which cells are solid (shaders/voxelize_mesh_*.comp): a cell is solid when the
// winding number of the mesh around its centre is nonzero, counted as the signed number of
// surface crossings along the +z ray through the centre. That number is well defined only for
// a closed, consistently oriented mesh, so validateMesh() requires one: after merging vertices
// at bit-identical positions, every edge must be used as often in one direction as in the
// other. Several shells, overlapping shells and inside-out meshes are fine (nonzero rule);
// zero-area triangles are fine (they cross no column). Parts thinner than a cell can fall
// between cell centres and are then not seen.
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "common/error.h"

namespace hf::obstacle {

// A mesh that is not closed and consistently oriented (validateMesh); the message says where.
class MeshNotClosed : public InvalidArgument {
 public:
  using InvalidArgument::InvalidArgument;
};

inline constexpr std::size_t kMaxMeshElements = 10'000'000;  // vertices and triangles each

struct TriangleMesh {
  std::vector<glm::vec3> vertices_m;      // local frame, m
  std::vector<glm::uvec3> triangles;      // vertex indices, counter-clockwise seen from outside
};

// Extent of a mesh's triangles in its local frame, for cheap world bounds of any pose.
struct MeshExtent {
  glm::vec3 lo{0.0f}, hi{0.0f};   // local axis-aligned box, m
  glm::vec3 centre{0.0f};         // of that box
  float radius = 0.0f;            // largest vertex distance from `centre`, m
  std::size_t triangles = 0;
  double triangle_size_sum = 0.0;     // sum over triangles of their local box diagonal, m
  double triangle_size_sq_sum = 0.0;  // the same, squared, m^2
};

// World pose of a rigid body: the object's matrix_world (local -> world, may scale), the
// velocity of its origin (the transform's translation) and its angular velocity (world frame).
struct RigidPose {
  glm::mat4 transform{1.0f};
  glm::vec3 velocity_m_s{0.0f};
  glm::vec3 angular_velocity_rad_s{0.0f};
  glm::vec3 originM() const { return glm::vec3(transform[3]); }
};

struct WorldBox {
  glm::vec3 lo{0.0f}, hi{0.0f};  // m
};

// Throws InvalidArgument (saying what to change) for an empty or oversized mesh, non-finite
// vertices, indices out of range, or a mesh that is not closed and consistently oriented.
void validateMesh(const TriangleMesh& mesh);
MeshExtent meshExtent(const TriangleMesh& mesh);
// Throws InvalidArgument for a non-finite, non-affine or singular transform.
void validateTransform(const glm::mat4& transform);
// A box that holds the transformed mesh: the intersection of the transformed local box's
// corners and the transformed bounding sphere (both conservative; O(1), no vertex loop).
WorldBox worldBox(const MeshExtent& extent, const glm::mat4& transform);
// An upper bound on the cell columns the crossings stage visits for this pose (each triangle
// visits the columns under its xy box), so a pose that would make the GPU work for seconds is
// refused rather than run.
double columnVisitBound(const MeshExtent& extent, const glm::mat4& transform, float cell_size_m);
inline constexpr double kMaxColumnVisits = 1e9;

}  // namespace hf::obstacle
