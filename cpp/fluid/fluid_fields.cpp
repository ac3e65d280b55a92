// SPDX-License-Identifier: GPL-3.0-or-later
#include "fluid/fluid_fields.h"

namespace hf::fluid {

PingPong::PingPong(const glm::ivec3& size, compute::TexelFormat f, const std::string& label)
    : tex{compute::Texture3D(size, f, label + " A"), compute::Texture3D(size, f, label + " B")} {}

FluidFields::FluidFields(const Grid& g)
    : vel{PingPong(g.faceSize(0), compute::TexelFormat::R32F, "velocity x"),
          PingPong(g.faceSize(1), compute::TexelFormat::R32F, "velocity y"),
          PingPong(g.faceSize(2), compute::TexelFormat::R32F, "velocity z")},
      density(g.res, compute::TexelFormat::R32F, "density"),
      temperature(g.res, compute::TexelFormat::R32F, "temperature"),
      pressure(g.res, compute::TexelFormat::R32F, "pressure"),
      rhs(g.res, compute::TexelFormat::R32F, "pressure rhs"),
      solid(g.res, compute::TexelFormat::R8UI, "solid mask"),
      solid_velocity(g.res, compute::TexelFormat::RGBA32F, "solid velocity"),
      cell_class(g.res, compute::TexelFormat::R8UI, "cell classes"),
      nbmask(g.res, compute::TexelFormat::R8UI, "neighbour mask"),
      face_open(g.res + 1, compute::TexelFormat::RGBA32F, "face open fractions"),
      vorticity(g.res, compute::TexelFormat::RGBA32F, "vorticity"),
      cell_force(g.res, compute::TexelFormat::RGBA32F, "cell force") {}

PingPong& FluidFields::scratchFor(int field_kind, const glm::ivec3& size) {
  auto& s = scratch[static_cast<std::size_t>(field_kind)];
  if (!s) s = std::make_unique<PingPong>(size, compute::TexelFormat::R32F, "MacCormack scratch");
  return *s;
}

std::size_t fieldBytes(const Grid& g) {
  // Per cell: velocity 3x2x4, MacCormack scratch 4x2x4, density/temperature/pressure 3x2x4,
  // rhs 4, three R8UI masks, solid velocity + vorticity + cell force + face fractions 4x16, and the multigrid
  // solver's (made on first use): CG vectors 4x4 + coarse levels (29 bytes a cell, 1/7 of the
  // cells in all) rounded up to 5.
  constexpr std::size_t kBytesPerCell = 24 + 32 + 24 + 4 + 3 + 64 + 16 + 5;
  return g.cells() * kBytesPerCell;
}

}  // namespace hf::fluid
