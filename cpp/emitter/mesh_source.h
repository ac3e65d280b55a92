// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A smoke source shaped by a closed triangle mesh (Mantaflow's mesh flow object): the mesh in
// its local frame, its pose (the object's matrix_world, set per step so it can be animated) and
// the values it emits. A source is not an obstacle: it writes no solid mask and no velocity; it
// only raises (or adds to) smoke and heat in the cells it covers, by the fraction it covers
// (emitter/mesh_emitter.h), with the same values and units as the sphere source
// (fluid::SourceEmission). The mesh passes obstacle::validateMesh (closed, consistently
// oriented), so its winding number, and with it its volume, is well defined.
#include <memory>

#include <glm/glm.hpp>

#include "fluid/fluid_params.h"
#include "fluid/grid.h"
#include "obstacle/triangle_mesh.h"

namespace hf::emitter {

// Sub-columns per cell along x and along y (kSourceSubsamples^2 per cell) at which the coverage
// is sampled; along z it is exact (the inside length of each sub-column in the cell).
inline constexpr int kSourceSubsamples = 4;

struct MeshSource {
  std::shared_ptr<const obstacle::TriangleMesh> mesh;  // local frame, m; validated, never changed
  obstacle::MeshExtent extent;                         // of `mesh`
  glm::mat4 transform{1.0f};                           // local -> world (matrix_world), m
  float density = 1.0f;                                // concentration (Hold) or per second (Rate)
  float temperature_k = 0.0f;                          // K above ambient (Hold) or K/s (Rate)
  fluid::SourceEmission emission = fluid::SourceEmission::Hold;
};

// The posed source: a usable transform (obstacle::validateTransform), a bounded voxelization
// cost, a world box that meets the domain (a source may reach out of it; the part outside
// emits nothing) and reaches no further than one domain size past any wall (so its
// fixed-point coordinates stay exact). Throws InvalidArgument saying what to change.
void validateSourcePose(const obstacle::MeshExtent& extent, const glm::mat4& transform, const fluid::Grid& grid);

// Validates the mesh, values and pose and builds the source (the mesh is moved in, then shared).
MeshSource makeMeshSource(obstacle::TriangleMesh mesh, const glm::mat4& transform, float density,
                          float temperature_k, fluid::SourceEmission emission, const fluid::Grid& grid);

}  // namespace hf::emitter
