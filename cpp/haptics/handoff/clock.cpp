// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/handoff/clock.h"

#include <time.h>

namespace hf::haptics {

double monotonicNowS() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace hf::haptics
