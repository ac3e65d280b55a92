// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/sphere_probe.h"


#include <cmath>

#include "compute/workgroup.h"

namespace hf::obstacle {

SphereProbe::SphereProbe(const fluid::Grid& grid)
    : grid_(grid),
      program_("voxelize_sphere.comp", compute::cellGroupDefines()),
      fractions_("sphere_fractions.comp", compute::cellGroupDefines()) {
  program_.set("u_res", grid.res);
  fractions_.set("u_res", grid.res);
  fractions_.set("u_min_open", kMinOpenFraction);
  program_.set("u_cell_size", grid.cell_size_m);
}

void SphereProbe::voxelize(compute::Texture3D& solid, compute::Texture3D& solid_velocity, const CellBox& region) {
  if (isEmpty(region)) return;
  solid.bindImage(0, compute::Access::Write);
  solid_velocity.bindImage(1, compute::Access::Write);
  program_.set("u_centre", grid_.toGrid(pose_.centre_m));
  program_.set("u_radius", pose_.radius_m / grid_.cell_size_m);
  program_.set("u_velocity", pose_.velocity_m_s);
  program_.set("u_angular", pose_.angular_velocity_rad_s);
  program_.set("u_origin", region.origin);
  program_.dispatch(region.extent);
}

bool SphereProbe::writeFaceFractions(compute::Texture3D& face_open, const CellBox& region) {
  if (!cut_cells_) return false;
  const CellBox faces = faceBox(region, grid_.res);
  if (isEmpty(faces)) return true;
  face_open.bindImage(0, compute::Access::Write);
  fractions_.set("u_centre", grid_.toGrid(pose_.centre_m));
  fractions_.set("u_ramp_radius", rampRadius(pose_.radius_m / grid_.cell_size_m));
  fractions_.set("u_origin", faces.origin);
  fractions_.dispatch(faces.extent);
  return true;
}

float SphereProbe::rampRadius(float radius_cells) {
  // Newton on f(x) = x^3 + x / 4 - r^3 (increasing, convex for x > 0) from x = r >= the root.
  const double r3 = std::pow(static_cast<double>(radius_cells), 3.0);
  double x = radius_cells;
  for (int i = 0; i < 8; ++i) x -= (x * x * x + 0.25 * x - r3) / (3.0 * x * x + 0.25);
  return static_cast<float>(x);
}

CellBox SphereProbe::bounds() const {
  const glm::vec3 c = grid_.toGrid(pose_.centre_m);
  const float r = pose_.radius_m / grid_.cell_size_m;
  return paddedCellBox(grid_.res, c - r, c + r);
}

}  // namespace hf::obstacle
