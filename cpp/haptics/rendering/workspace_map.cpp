// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/rendering/workspace_map.h"

#include <cmath>
#include <string>

#include "common/error.h"

namespace hf::haptics {

void WorkspaceMap::validate() const {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(scale[a]) || scale[a] == 0.0f) {
      throw InvalidArgument("workspace_scale must be finite and nonzero on every axis (domain m per device m), got " +
                            std::to_string(scale[a]) + " on axis " + std::to_string(a));
    }
    if (!std::isfinite(offset_m[a])) throw InvalidArgument("workspace_offset must be finite (m)");
  }
  if (!std::isfinite(force_gain) || force_gain < 0.0f) {
    throw InvalidArgument("force_gain must be a finite number >= 0 (device N per fluid N), got " +
                          std::to_string(force_gain));
  }
}

}  // namespace hf::haptics
