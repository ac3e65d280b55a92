#pragma once
// Argument checks shared by the virtual devices (messages say what to change).
#include <string>

namespace hf::haptics {

// max_force_n must be finite and > 0.
void checkMaxForce(float max_force_n, const std::string& who);

}  // namespace hf::haptics
