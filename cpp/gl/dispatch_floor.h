// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The cost floor of a per-cell dispatch on the current GL device (benchmarks only): how much a
// step's invocation count alone costs before any stage does work. On llvmpipe a launched
// invocation costs CPU time even when it does nothing, so a step's invocations times that cost
// is a lower bound for the step on this machine, whatever its shaders compute.
#include <glm/glm.hpp>

namespace hf::gl {

struct DispatchFloor {
  glm::ivec3 cells{0};      // the grid each dispatch covered (one invocation per cell)
  int repeats = 0;          // timed dispatches of each kind (after one untimed), each to glFinish
  double launched = 0.0;    // invocations per dispatch (workgroups x local size)
  // Per launched invocation, nanoseconds, the median dispatch of the repeats:
  double empty_wall_ns = 0.0;  // a dispatch whose invocations do nothing: wall time (glFinish)
  double empty_cpu_ns = 0.0;   // the same, CPU time of this process (all threads: llvmpipe's
                               // shader threads; near 0 on a GPU)
  double store_wall_ns = 0.0;  // each invocation stores one R32F texel: wall time
  double store_cpu_ns = 0.0;   // the same, process CPU time
};

// Runs `repeats` dispatches of each kind over `cells` on the calling thread's current context
// and times them. InvalidArgument if a cell count is < 1 or above the device's 3D texture size,
// or repeats < 1.
DispatchFloor measureDispatchFloor(const glm::ivec3& cells, int repeats);

}  // namespace hf::gl
