#include "haptics/device_checks.h"

#include <cmath>

#include "common/error.h"

namespace hf::haptics {

void checkMaxForce(float max_force_n, const std::string& who) {
  if (!std::isfinite(max_force_n) || max_force_n <= 0.0f) {
    throw InvalidArgument(who + ": max_force must be a positive number of newtons, got " + std::to_string(max_force_n));
  }
}

}  // namespace hf::haptics
