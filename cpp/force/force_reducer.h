#pragma once
// Force of the fluid on the body, reduced on the GPU: every exposed face between a boundary
// cell and a surrounding cell adds (dynamic pressure of the surrounding cell + hydrostatic
// pressure at the face) x face area along the inward normal. Workgroups sum their faces in
// shared memory; one more workgroup sums the groups (gl::GroupReducer). Nothing is read back
// here: the caller reads the result slot with the step's single read-back.
#include "fluid/grid.h"
#include "gl/compute_program.h"
#include "gl/group_reducer.h"
#include "gl/texture3d.h"
#include "obstacle/obstacle.h"

namespace hf::force {

struct BodyForce {
  glm::vec3 force_n{0.0f};  // N, on the body, from the fluid
  int exposed_faces = 0;    // boundary/surrounding face pairs summed
};

class ForceReducer {
 public:
  explicit ForceReducer(const fluid::Grid& grid);
  // `rho_g`: fluid density times gravity (N/m^3); `reference_m`: world point of 0 hydrostatic Pa.
  void reduce(const gl::Texture3D& pressure, const gl::Texture3D& cell_class, const obstacle::CellBox& box,
              const glm::vec3& rho_g, const glm::vec3& reference_m, gl::GroupReducer& reducer, std::size_t slot);
  static BodyForce decode(const glm::vec4& slot_value);

 private:
  fluid::Grid grid_;
  gl::ComputeProgram faces_;
};

}  // namespace hf::force
