// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The values a numeric setting takes: min .. max, max itself refused when max_exclusive. The
// engine's checks compare with these, and the bindings report them (FluidSettings.limits()), so
// a host's fields offer exactly what the engine takes.

namespace hf {

struct Range {
  double min = 0.0;
  double max = 0.0;
  bool max_exclusive = false;
};

}  // namespace hf
