// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Force and torque of the fluid on the body, reduced on the GPU: every exposed face between a
// boundary cell and a surrounding cell adds F_f = (dynamic pressure of the surrounding cell +
// hydrostatic pressure at the face) x face area along the inward normal, and (x_f - p0) x F_f
// about a reference point p0 near the body; the same pass sums the solid cells' positions
// (their centroid). Workgroups sum in shared memory; one more workgroup per result sums the
// groups (compute::GroupReducer). Nothing is read back here: the caller reads the three result slots
// with the step's single read-back and decode()s them, moving the torque to the centre asked for.
#include <optional>
#include <vector>

#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "compute/group_reducer.h"
#include "compute/texture3d.h"
#include "obstacle/obstacle.h"

namespace hf::force {

struct BodyForce {
  glm::vec3 force_n{0.0f};          // N, on the body, from the fluid
  glm::vec3 torque_n_m{0.0f};       // N m, about torque_centre_m
  glm::vec3 torque_centre_m{0.0f};  // world point the torque is taken about, m
  glm::vec3 centroid_m{0.0f};       // of the solid cells' centres, m (p0 when there are none)
  int exposed_faces = 0;            // boundary/surrounding face pairs summed
  int solid_cells = 0;              // boundary + inside cells in the box
};

// Where the three sums land in the reducer's results.
struct ForceSlots {
  std::size_t force = 0;     // (sum F_f, faces)
  std::size_t torque = 1;    // (sum (x_f - p0) x F_f, 0)
  std::size_t centroid = 2;  // (sum (x_c - p0) over solid cells, cells)
};

class ForceReducer {
 public:
  static constexpr std::size_t kParts = 3;  // vec4 partials per workgroup

  explicit ForceReducer(const fluid::Grid& grid);
  // Partials the reducer must hold for a box of the whole grid.
  static std::size_t partialsNeeded(const fluid::Grid& grid);
  // `face_open`: the faces' open fractions, geometric when `cut_cells`, else binary from the voxels;
  // `rho_g`: fluid density times gravity (N/m^3) (only its difference across a face enters);
  // `p0_m`: world point near the body that the torque and centroid sums are taken about.
  void reduce(const compute::Texture3D& pressure, const compute::Texture3D& cell_class, const compute::Texture3D& nbmask,
              const compute::Texture3D& face_open, const obstacle::CellBox& box,
              bool cut_cells, const glm::vec3& rho_g, const glm::vec3& p0_m,
              compute::GroupReducer& reducer, const ForceSlots& slots);
  // The sums -> force and torque about `centre_m` (nullopt: the solid cells' centroid), using
  // tau_c = tau_p0 - (c - p0) x F.
  static BodyForce decode(const std::vector<glm::vec4>& results, const ForceSlots& slots, const glm::vec3& p0_m,
                          const std::optional<glm::vec3>& centre_m);

 private:
  fluid::Grid grid_;
  compute::ComputeProgram faces_;
};

}  // namespace hf::force
