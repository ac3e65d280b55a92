// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/compute_program.h"

namespace hf::compute {

ComputeProgram::ComputeProgram(const std::string& file, const Defines& defines)
    : name_(file), impl_(currentDevice().makeProgram(file, defines)) {}

ComputeProgram::~ComputeProgram() = default;

}  // namespace hf::compute
