// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Argument checks shared by the virtual devices (messages say what to change).
#include <string>

namespace hf::haptics {

// The largest max_force a virtual device accepts, N: far above any desktop haptic device (a
// Falcon gives 8.9 N); a larger value is a typo, and would become the session's force cap.
inline constexpr float kMaxDeviceForceN = 1000.0f;

// max_force_n must be finite, > 0 and at most kMaxDeviceForceN.
void checkMaxForce(float max_force_n, const std::string& who);

}  // namespace hf::haptics
