// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Every GPU field of the simulation. Velocity is staggered (MAC): vel[0] on x-faces
// (nx+1,ny,nz), vel[1] on y-faces, vel[2] on z-faces; the rest are cell-centred.
#include <array>
#include <memory>

#include "fluid/grid.h"
#include "compute/texture3d.h"

namespace hf::fluid {

// Two textures of one field: read `cur()`, write `next()`, then swap().
struct PingPong {
  PingPong(const glm::ivec3& size, compute::TexelFormat f, const std::string& label);
  compute::Texture3D& cur() { return tex[index]; }
  compute::Texture3D& next() { return tex[1 - index]; }
  void swap() { index = 1 - index; }
  std::array<compute::Texture3D, 2> tex;
  int index = 0;
};

// Image unit of FluidFields::face_open in every stage that reads it (FACE_OPEN_UNIT in common.glsl).
constexpr unsigned kFaceOpenUnit = 6;

struct FluidFields {
  explicit FluidFields(const Grid& grid);

  std::array<PingPong, 3> vel;  // m/s on faces
  PingPong density;             // smoke concentration
  PingPong temperature;         // K above ambient
  PingPong pressure;            // dynamic pressure, Pa
  compute::Texture3D rhs;            // pressure equation right-hand side, Pa
  compute::Texture3D solid;          // R8UI 1 = covered by the probe (written by the voxelizer)
  compute::Texture3D solid_velocity; // RGBA32F rigid velocity at solid cell centres, m/s
  compute::Texture3D cell_class;     // R8UI seed classes (obstacle/cell_class.h)
  compute::Texture3D nbmask;         // R8UI neighbour mask (shaders/common.glsl)
  compute::Texture3D face_open;      // RGBA32F open fraction of the x/y/z faces, res + 1 texels (common.glsl)
  compute::Texture3D vorticity;      // RGBA32F curl (1/s) and its magnitude
  compute::Texture3D cell_force;     // RGBA32F body acceleration at cells, m/s^2
  // MacCormack scratch (forward and backward passes), made on first use.
  std::array<std::unique_ptr<PingPong>, 4> scratch;  // u, v, w, scalar

  PingPong& scratchFor(int field_kind, const glm::ivec3& size);
};

// Bytes of GPU memory a grid's fields take (MacCormack scratch and multigrid included).
std::size_t fieldBytes(const Grid& grid);

}  // namespace hf::fluid
