// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/mesh_probe.h"


#include <algorithm>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "compute/workgroup.h"

namespace hf::obstacle {
namespace {

constexpr int kFixedPointRange = 1 << 14;  // largest fixed-point coordinate: keeps edge functions in int32

// The per-vertex and per-triangle stages dispatch ceil(n / kLinearGroup) groups along x, and GL
// guarantees only 65535 groups per axis: the mesh size limit must fit in one dispatch. Likewise
// a column's crossing count (at most one per triangle) must fit in the int32 atomics.
static_assert(kMaxMeshElements <= std::size_t{65535} * compute::kLinearGroup,
              "kMaxMeshElements exceeds one linear dispatch (65535 groups of kLinearGroup)");
static_assert(kMaxMeshElements <= std::size_t{0x7fffffff}, "crossing counts must fit in int32");

}  // namespace

MeshProbe::MeshProbe(const fluid::Grid& grid)
    : grid_(grid),
      crossings_(grid.cells() * sizeof(std::int32_t), "mesh crossings of the " + std::to_string(grid.res.x) + "x" +
                                                          std::to_string(grid.res.y) + "x" + std::to_string(grid.res.z) +
                                                          " grid (4 bytes per cell)"),
      crossings_program_("voxelize_mesh_crossings.comp", compute::linearGroupDefines()),
      fill_("voxelize_mesh_fill.comp", compute::cellGroupDefines()),
      fine_crossings_("voxelize_mesh_crossings.comp", compute::linearGroupDefines()),
      winding_("voxelize_mesh_winding.comp", compute::cellGroupDefines()),
      fractions_("mesh_fractions.comp", compute::cellGroupDefines()) {
  const int widest = std::max(grid.res.x, grid.res.y);
  while (widest * subcell_ * 2 <= kFixedPointRange) subcell_ *= 2;
  if (widest * subcell_ > kFixedPointRange) {
    throw InvalidArgument("mesh probes support at most " + std::to_string(kFixedPointRange / 2) +
                          " cells along x and y; lower the resolution");
  }
  crossings_program_.set("u_res", grid.res);
  crossings_program_.set("u_subcell", subcell_);
  fill_.set("u_res", grid.res);
  fill_.set("u_cell_size", grid.cell_size_m);
  fractions_.set("u_res", grid.res);
  fractions_.set("u_min_open", kMinOpenFraction);
}

int MeshProbe::fineCellsFor(std::size_t box_cells) {
  const std::size_t cube = static_cast<std::size_t>(kFineCells) * kFineCells * kFineCells;
  return box_cells * cube <= kMaxFineCells ? kFineCells : 2;
}

void MeshProbe::setMesh(std::shared_ptr<const TriangleMesh> mesh) {
  if (!mesh) throw Error("MeshProbe::setMesh: no mesh");
  if (mesh == mesh_) return;
  gpu_mesh_.upload(*mesh, "mesh");
  mesh_ = std::move(mesh);
  extent_ = meshExtent(*mesh_);
}

void MeshProbe::setPose(const RigidPose& pose) { pose_ = pose; }

void MeshProbe::voxelize(compute::Texture3D& solid, compute::Texture3D& solid_velocity, const CellBox& region) {
  if (!mesh_) throw Error("MeshProbe::voxelize: no mesh was set");
  if (isEmpty(region)) return;
  gpu_mesh_.pose(localToLattice(pose_.transform, grid_.origin_m, grid_.cell_size_m));
  gpu_mesh_.dispatchCrossings(crossings_program_, crossings_);

  crossings_.bind(0);
  solid.bindImage(0, compute::Access::Write);
  solid_velocity.bindImage(1, compute::Access::Write);
  fill_.set("u_origin", grid_.toGrid(pose_.originM()));
  fill_.set("u_velocity", pose_.velocity_m_s);
  fill_.set("u_angular", pose_.angular_velocity_rad_s);
  fill_.set("u_first_column", region.origin);
  fill_.dispatch(glm::ivec3(region.extent.x, region.extent.y, 1));  // each column whole, bottom to top
}

bool MeshProbe::writeFaceFractions(compute::Texture3D& face_open, const CellBox& region) {
  if (!cut_cells_ || !mesh_) return false;
  const CellBox box = bounds();
  if (isEmpty(box)) return false;
  const std::size_t box_cells = static_cast<std::size_t>(box.extent.x) * box.extent.y * box.extent.z;
  const int s = fineCellsFor(box_cells);
  const glm::ivec3 fine_res = box.extent * s;
  const std::size_t fine_cells = box_cells * s * s * s;
  int subcell = 2;
  const int widest = std::max(fine_res.x, fine_res.y);
  while (widest * subcell * 2 <= kFixedPointRange) subcell *= 2;
  if (widest * subcell > kFixedPointRange) {
    throw InvalidArgument("cut cells: the mesh probe's box is " + std::to_string(box.extent.x) + "x" +
                          std::to_string(box.extent.y) + " cells wide, more than its fine voxelization holds (" +
                          std::to_string(kFixedPointRange / 2 / s) + "); scale the mesh down or turn cut_cells off");
  }
  if (!fine_winding_ || fine_winding_->bytes() < fine_cells * sizeof(std::int32_t)) {
    fine_winding_.reset();
    fine_winding_ = std::make_unique<compute::StorageBuffer>(fine_cells * sizeof(std::int32_t),
                                                        "cut cells: the mesh probe's fine voxelization (" +
                                                            std::to_string(fine_cells) + " fine cells, 4 bytes each)");
  }
  const CellBox faces = faceBox(region, grid_.res);
  if (isEmpty(faces)) return true;  // nothing asked for: no fine voxelization either
  // local -> fine grid units: s x (grid units - the box's first cell)
  gpu_mesh_.pose(localToLattice(pose_.transform, grid_.origin_m, grid_.cell_size_m / s, box.origin * s));
  fine_crossings_.set("u_res", fine_res);
  fine_crossings_.set("u_subcell", subcell);
  gpu_mesh_.dispatchCrossings(fine_crossings_, *fine_winding_);

  fine_winding_->bind(0);
  winding_.set("u_res", fine_res);
  winding_.dispatch(glm::ivec3(fine_res.x, fine_res.y, 1));

  face_open.bindImage(0, compute::Access::Write);
  fractions_.set("u_box_origin", box.origin);
  fractions_.set("u_fine_res", fine_res);
  fractions_.set("u_fine", s);
  fractions_.set("u_first", faces.origin);
  fractions_.dispatch(faces.extent);
  return true;
}

CellBox MeshProbe::bounds() const {
  if (!mesh_) return {};
  const WorldBox w = worldBox(extent_, pose_.transform);
  return paddedCellBox(grid_.res, grid_.toGrid(w.lo), grid_.toGrid(w.hi));
}

glm::vec3 MeshProbe::referencePointM() const {
  if (!mesh_) return pose_.originM();
  const WorldBox w = worldBox(extent_, pose_.transform);
  return 0.5f * (w.lo + w.hi);
}

}  // namespace hf::obstacle
