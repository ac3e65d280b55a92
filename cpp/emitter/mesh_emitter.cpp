// SPDX-License-Identifier: GPL-3.0-or-later
#include "emitter/mesh_emitter.h"


#include <algorithm>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "compute/workgroup.h"

namespace hf::emitter {
namespace {

// Largest |lattice coordinate|: vertices lie within one domain size of the walls
// (validateSourcePose), i.e. within [-widest, 2 widest] cells, so a lattice of at most
// kLatticeRange / (2 widest) steps per cell keeps every coordinate below it and every coordinate
// difference in int32; edge functions (products) are computed in double, exact below 2^53.
constexpr int kLatticeRange = 1 << 22;

static_assert(obstacle::kMaxMeshElements <= std::size_t{65535} * compute::kLinearGroup,
              "kMaxMeshElements exceeds one linear dispatch (65535 groups of kLinearGroup)");

std::string gridText(const glm::ivec3& r) {
  return std::to_string(r.x) + "x" + std::to_string(r.y) + "x" + std::to_string(r.z);
}

}  // namespace

MeshEmitter::MeshEmitter(const fluid::Grid& grid)
    : grid_(grid),
      crossings_(grid.cells() * 2 * sizeof(std::int32_t),
                 "smoke source crossings of the " + gridText(grid.res) + " grid (8 bytes per cell)"),
      coverage_(grid.res, compute::TexelFormat::R32F, "smoke source coverage"),
      crossings_program_("emit_mesh_crossings.comp", compute::linearGroupDefines()),
      coverage_program_("emit_mesh_coverage.comp", compute::cellGroupDefines()),
      emit_("emit_coverage.comp", compute::cellGroupDefines()) {
  const int widest = std::max(grid.res.x, grid.res.y);
  if (2 * widest * subcell_ > kLatticeRange) {
    throw InvalidArgument("mesh smoke sources support at most " + std::to_string(kLatticeRange / (2 * subcell_)) +
                          " cells along x and y; lower the resolution");
  }
  while (2 * widest * subcell_ * 2 <= kLatticeRange) subcell_ *= 2;
  crossings_program_.set("u_res", grid.res);
  crossings_program_.set("u_subcell", subcell_);
  crossings_program_.set("u_samples", kSourceSubsamples);
  crossings_program_.set("u_limit", kLatticeRange);
  coverage_program_.set("u_res", grid.res);
  coverage_program_.set("u_samples", kSourceSubsamples);
  emit_.set("u_res", grid.res);
}

void MeshEmitter::setSource(const MeshSource& source) {
  if (!source.mesh) throw Error("MeshEmitter::setSource: no mesh");
  if (source.mesh != uploaded_) {
    gpu_mesh_.upload(*source.mesh, "smoke source");
    uploaded_ = source.mesh;
  }
  source_ = source;
}

void MeshEmitter::voxelize() {
  if (!uploaded_) throw Error("MeshEmitter::voxelize: no source was set");
  gpu_mesh_.pose(obstacle::localToLattice(source_.transform, grid_.origin_m, grid_.cell_size_m));
  gpu_mesh_.dispatchCrossings(crossings_program_, crossings_);

  crossings_.bind(0);
  coverage_.bindImage(0, compute::Access::Write);
  coverage_program_.dispatch(glm::ivec3(grid_.res.x, grid_.res.y, 1));
}

void MeshEmitter::emit(compute::Texture3D& density, compute::Texture3D& temperature, const compute::Texture3D& nbmask, float dt_s) {
  const obstacle::CellBox box = bounds();
  if (glm::any(glm::lessThanEqual(box.extent, glm::ivec3(0)))) return;
  density.bindImage(0, compute::Access::ReadWrite);
  temperature.bindImage(1, compute::Access::ReadWrite);
  nbmask.bindImage(2, compute::Access::Read);
  coverage_.bindImage(3, compute::Access::Read);
  emit_.set("u_origin", box.origin);
  emit_.set("u_density_value", source_.density);
  emit_.set("u_temperature_value", source_.temperature_k);
  emit_.set("u_rate", source_.emission == fluid::SourceEmission::Rate ? 1 : 0);
  emit_.set("u_dt", dt_s);
  emit_.dispatch(box.extent);
}

obstacle::CellBox MeshEmitter::bounds() const {
  if (!uploaded_) return {};
  const obstacle::WorldBox w = obstacle::worldBox(source_.extent, source_.transform);
  return obstacle::paddedCellBox(grid_.res, grid_.toGrid(w.lo), grid_.toGrid(w.hi));
}

}  // namespace hf::emitter
