// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The seed's probe: a rigid sphere, voxelized on the GPU by cell centre.
#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "obstacle/obstacle.h"

namespace hf::obstacle {

struct SpherePose {
  glm::vec3 centre_m{0.0f};            // world position, m
  float radius_m = 0.1f;               // m
  glm::vec3 velocity_m_s{0.0f};        // linear velocity, m/s
  glm::vec3 angular_velocity_rad_s{0.0f};  // about the centre, rad/s
};

class SphereProbe : public Obstacle {
 public:
  explicit SphereProbe(const fluid::Grid& grid);
  void setPose(const SpherePose& pose) { pose_ = pose; }
  const SpherePose& pose() const { return pose_; }
  // Both dispatch over the region asked for, from its first cell (the last workgroups may write
  // a few cells past it, with their current values).
  void voxelize(compute::Texture3D& solid, compute::Texture3D& solid_velocity, const CellBox& region) override;
  // The faces' open fractions from the sphere itself (shaders/sphere_fractions.comp) when cut
  // cells are on (setCutCells); otherwise false, and the voxels' binary fractions are used.
  bool writeFaceFractions(compute::Texture3D& face_open, const CellBox& region) override;
  void setCutCells(bool on) { cut_cells_ = on; }
  // Cut cells smooth the sphere's indicator into a radial ramp one cell wide; the ramp's centre
  // radius (grid units) whose ball-plus-ramp volume, 4/3 pi (rc^3 + rc / 4), is the sphere's
  // 4/3 pi r^3 (r >= 1 cell, so rc > 1/2 and the ramp never reaches the centre).
  static float rampRadius(float radius_cells);
  CellBox bounds() const override;
  glm::vec3 referencePointM() const override { return pose_.centre_m; }

 private:
  fluid::Grid grid_;
  SpherePose pose_;
  compute::ComputeProgram program_;
  compute::ComputeProgram fractions_;
  bool cut_cells_ = false;
};

}  // namespace hf::obstacle
