#include "obstacle/classifier.h"

#include <GL/gl.h>

#include "fluid/fluid_fields.h"
#include "gl/workgroup.h"

namespace hf::obstacle {

Classifier::Classifier(const fluid::Grid& grid)
    : grid_(grid),
      program_("classify.comp", gl::cellGroupDefines()),
      binary_("binary_fractions.comp", gl::cellGroupDefines()) {
  program_.set("u_res", grid.res);
  binary_.set("u_res", grid.res);
}

void Classifier::binaryFractions(const gl::Texture3D& solid, gl::Texture3D& face_open) {
  solid.bindImage(1, GL_READ_ONLY);
  face_open.bindImage(0, GL_WRITE_ONLY);
  binary_.dispatch(grid_.res + 1);
}

void Classifier::classify(const gl::Texture3D& solid, const gl::Texture3D& face_open, gl::Texture3D& cell_class,
                          gl::Texture3D& nbmask, bool open_top) {
  solid.bindImage(2, GL_READ_ONLY);
  face_open.bindImage(fluid::kFaceOpenUnit, GL_READ_ONLY);
  cell_class.bindImage(0, GL_WRITE_ONLY);
  nbmask.bindImage(1, GL_WRITE_ONLY);
  program_.set("u_open_top", open_top ? 1 : 0);
  program_.dispatch(grid_.res);
}

}  // namespace hf::obstacle
