#include "obstacle/sphere_probe.h"

#include <GL/gl.h>

#include "gl/workgroup.h"

namespace hf::obstacle {

SphereProbe::SphereProbe(const fluid::Grid& grid)
    : grid_(grid),
      program_("voxelize_sphere.comp", gl::cellGroupDefines()),
      fractions_("sphere_fractions.comp", gl::cellGroupDefines()) {
  program_.set("u_res", grid.res);
  fractions_.set("u_res", grid.res);
  program_.set("u_cell_size", grid.cell_size_m);
}

void SphereProbe::voxelize(gl::Texture3D& solid, gl::Texture3D& solid_velocity) {
  solid.bindImage(0, GL_WRITE_ONLY);
  solid_velocity.bindImage(1, GL_WRITE_ONLY);
  program_.set("u_centre", grid_.toGrid(pose_.centre_m));
  program_.set("u_radius", pose_.radius_m / grid_.cell_size_m);
  program_.set("u_velocity", pose_.velocity_m_s);
  program_.set("u_angular", pose_.angular_velocity_rad_s);
  program_.dispatch(grid_.res);
}

bool SphereProbe::writeFaceFractions(gl::Texture3D& face_open) {
  if (!cut_cells_) return false;
  face_open.bindImage(0, GL_WRITE_ONLY);
  fractions_.set("u_centre", grid_.toGrid(pose_.centre_m));
  fractions_.set("u_radius", pose_.radius_m / grid_.cell_size_m);
  fractions_.dispatch(grid_.res + 1);
  return true;
}

CellBox SphereProbe::bounds() const {
  const glm::vec3 c = grid_.toGrid(pose_.centre_m);
  const float r = pose_.radius_m / grid_.cell_size_m;
  return paddedCellBox(grid_.res, c - r, c + r);
}

}  // namespace hf::obstacle
