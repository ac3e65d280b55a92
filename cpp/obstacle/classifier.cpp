// SPDX-License-Identifier: GPL-3.0-or-later
#include "obstacle/classifier.h"


#include "fluid/fluid_fields.h"
#include "compute/workgroup.h"

namespace hf::obstacle {

Classifier::Classifier(const fluid::Grid& grid)
    : grid_(grid),
      program_("classify.comp", compute::cellGroupDefines()),
      binary_("binary_fractions.comp", compute::cellGroupDefines()) {
  program_.set("u_res", grid.res);
  binary_.set("u_res", grid.res);
}

void Classifier::binaryFractions(const compute::Texture3D& solid, compute::Texture3D& face_open, const CellBox& region) {
  const CellBox faces = faceBox(region, grid_.res);
  if (isEmpty(faces)) return;
  solid.bindImage(1, compute::Access::Read);
  face_open.bindImage(0, compute::Access::Write);
  binary_.set("u_origin", faces.origin);
  binary_.dispatch(faces.extent);
}

void Classifier::classify(const compute::Texture3D& solid, const compute::Texture3D& face_open, compute::Texture3D& cell_class,
                          compute::Texture3D& nbmask, bool open_top, const CellBox& region) {
  if (isEmpty(region)) return;
  solid.bindImage(2, compute::Access::Read);
  face_open.bindImage(fluid::kFaceOpenUnit, compute::Access::Read);
  cell_class.bindImage(0, compute::Access::Write);
  nbmask.bindImage(1, compute::Access::Write);
  program_.set("u_open_top", open_top ? 1 : 0);
  program_.set("u_origin", region.origin);
  program_.dispatch(region.extent);
}

}  // namespace hf::obstacle
