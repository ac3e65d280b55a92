// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The CPU device (compute::Device): fields in host memory, the kernels of shaders/ compiled as
// C++ (cpu/kernels/), run by a pool of threads. GL's model is kept where the stages rely on it:
// image units and storage-buffer bindings are the device's state, set by bindImage()/bind() and
// read by the next dispatch; a load outside an image gives 0 and a store outside it is dropped.
#include <memory>
#include <optional>

#include "compute/compute_worker.h"
#include "compute/device.h"

namespace hf::cpu {

// The environment variable that sets the CPU device's threads when the caller does not (0 or
// unset: one per core the process may run on).
inline constexpr const char* kCpuThreadsEnv = "HAPTICFLUID_CPU_THREADS";
inline constexpr int kMaxThreads = 256;

// The threads a CPU device uses for `requested` (0: HAPTICFLUID_CPU_THREADS, else one per core
// the process may run on). Throws hf::InvalidArgument for a value outside 0..kMaxThreads,
// naming where it came from.
int resolveThreads(int requested);

// Makes the device on the calling thread, which becomes its thread; `niceness` as for the GL
// device (the pool's threads are started after it is applied, so they share it). Its kernels
// run with denormal floats flushed to zero (cpu/float_mode.h). `x86_v3`:
// run the x86-64-v3 build of the loops (cpu/kernel.h); none: when the CPU has it.
std::unique_ptr<compute::Device> makeCpuDevice(int threads, std::optional<int> niceness,
                                               std::optional<bool> x86_v3 = std::nullopt);

// A worker thread with a CPU device.
class CpuWorker : public compute::ComputeWorker {
 public:
  explicit CpuWorker(int threads = 0, std::optional<int> niceness = std::nullopt,
                     std::optional<bool> x86_v3 = std::nullopt)
      : ComputeWorker([threads, niceness, x86_v3] { return makeCpuDevice(threads, niceness, x86_v3); }) {}
};

}  // namespace hf::cpu
