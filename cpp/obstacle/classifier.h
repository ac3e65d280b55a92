#pragma once
// Turns the solid mask into the seed's four cell classes and the pressure stages' neighbour
// mask (one GPU pass over the grid).
#include "fluid/grid.h"
#include "gl/compute_program.h"
#include "gl/texture3d.h"

namespace hf::obstacle {

class Classifier {
 public:
  explicit Classifier(const fluid::Grid& grid);
  void classify(const gl::Texture3D& solid, gl::Texture3D& cell_class, gl::Texture3D& nbmask, bool open_top);

 private:
  fluid::Grid grid_;
  gl::ComputeProgram program_;
};

}  // namespace hf::obstacle
