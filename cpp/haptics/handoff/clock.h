// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The one clock of the haptics layer: CLOCK_MONOTONIC in seconds. It is the clock of
// std::chrono::steady_clock and of Python's time.monotonic(), so times pushed from Python
// (HostDevice) and DeviceState::time_s compare directly.
namespace hf::haptics {

double monotonicNowS();

}  // namespace hf::haptics
