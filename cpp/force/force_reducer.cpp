#include "force/force_reducer.h"

#include <GL/gl.h>

#include <cmath>

#include "gl/workgroup.h"

namespace hf::force {

ForceReducer::ForceReducer(const fluid::Grid& grid) : grid_(grid), faces_("force_faces.comp", gl::groupSumDefines()) {
  faces_.set("u_res", grid.res);
  faces_.set("u_face_area", grid.cell_size_m * grid.cell_size_m);
  faces_.set("u_cell_size", grid.cell_size_m);
}

void ForceReducer::reduce(const gl::Texture3D& pressure, const gl::Texture3D& cell_class,
                          const obstacle::CellBox& box, const glm::vec3& rho_g, const glm::vec3& reference_m,
                          gl::GroupReducer& reducer, std::size_t slot) {
  if (glm::any(glm::lessThanEqual(box.extent, glm::ivec3(0)))) {
    reducer.bindPartials(0);
    reducer.reduce(0, slot);  // an empty box gives a zero force
    return;
  }
  pressure.bindImage(0, GL_READ_ONLY);
  cell_class.bindImage(1, GL_READ_ONLY);
  reducer.bindPartials(0);
  faces_.set("u_origin", box.origin);
  faces_.set("u_extent", box.extent);
  faces_.set("u_rho_g", rho_g);
  faces_.set("u_reference", grid_.toGrid(reference_m));
  faces_.dispatch(box.extent);
  reducer.reduce(gl::groupCount(box.extent), slot);
}

BodyForce ForceReducer::decode(const glm::vec4& v) {
  BodyForce f;
  f.force_n = glm::vec3(v);
  f.exposed_faces = static_cast<int>(std::lround(v.w));
  return f;
}

}  // namespace hf::force
