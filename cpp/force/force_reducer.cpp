// SPDX-License-Identifier: GPL-3.0-or-later
#include "force/force_reducer.h"


#include <cmath>

#include "common/error.h"
#include "fluid/fluid_fields.h"
#include "compute/workgroup.h"

namespace hf::force {

ForceReducer::ForceReducer(const fluid::Grid& grid) : grid_(grid), faces_("force_faces.comp", compute::groupSumDefines()) {
  faces_.set("u_res", grid.res);
  faces_.set("u_face_area", grid.cell_size_m * grid.cell_size_m);
  faces_.set("u_cell_size", grid.cell_size_m);
}

std::size_t ForceReducer::partialsNeeded(const fluid::Grid& grid) { return kParts * compute::groupCount(grid.res); }

void ForceReducer::reduce(const compute::Texture3D& pressure, const compute::Texture3D& cell_class,
                          const compute::Texture3D& nbmask, const compute::Texture3D& face_open, const obstacle::CellBox& box,
                          bool cut_cells, const glm::vec3& rho_g, const glm::vec3& p0_m, compute::GroupReducer& reducer, const ForceSlots& slots) {
  if (glm::any(glm::lessThanEqual(box.extent, glm::ivec3(0)))) {
    reducer.bindPartials(0);
    for (std::size_t slot : {slots.force, slots.torque, slots.centroid}) reducer.reduce(0, slot);  // zeros
    return;
  }
  const std::size_t groups = compute::groupCount(box.extent);
  if (kParts * groups > reducer.maxGroups()) throw Error("force: the reducer holds too few partials for the box");
  pressure.bindImage(0, compute::Access::Read);
  cell_class.bindImage(1, compute::Access::Read);
  nbmask.bindImage(2, compute::Access::Read);
  face_open.bindImage(fluid::kFaceOpenUnit, compute::Access::Read);
  reducer.bindPartials(0);
  faces_.set("u_origin", box.origin);
  faces_.set("u_extent", box.extent);
  faces_.set("u_rho_g", rho_g);
  faces_.set("u_cut_cells", cut_cells ? 1 : 0);
  faces_.set("u_p0", grid_.toGrid(p0_m));
  faces_.dispatch(box.extent);
  reducer.reduce(groups, slots.force, 0);
  reducer.reduce(groups, slots.torque, groups);
  reducer.reduce(groups, slots.centroid, 2 * groups);
}

BodyForce ForceReducer::decode(const std::vector<glm::vec4>& results, const ForceSlots& slots,
                               const glm::vec3& p0_m, const std::optional<glm::vec3>& centre_m) {
  const glm::vec4 f = results.at(slots.force), t = results.at(slots.torque), c = results.at(slots.centroid);
  BodyForce out;
  out.force_n = glm::vec3(f);
  out.exposed_faces = static_cast<int>(std::lround(f.w));
  out.solid_cells = static_cast<int>(std::lround(c.w));
  out.centroid_m = out.solid_cells > 0 ? p0_m + glm::vec3(c) / c.w : p0_m;
  out.torque_centre_m = centre_m ? *centre_m : out.centroid_m;
  out.torque_n_m = glm::vec3(t) - glm::cross(out.torque_centre_m - p0_m, out.force_n);
  return out;
}

}  // namespace hf::force
