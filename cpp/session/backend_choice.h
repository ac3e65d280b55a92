// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Which device a simulation runs on: the GPU backend (OpenGL compute on an EGL device) or the
// CPU backend (the same kernels compiled as C++). "auto" takes a hardware GPU when one gives a
// context, and the CPU backend otherwise: where the only GL device is a software renderer
// (Mesa's llvmpipe), the CPU backend runs the same step several times faster.
#include <memory>
#include <optional>
#include <string>

#include "compute/compute_worker.h"

namespace hf::session {

// The environment variable that chooses the backend when the settings leave it empty.
inline constexpr const char* kBackendEnv = "HAPTICFLUID_BACKEND";

enum class BackendRequest { Auto, Gpu, Cpu };

// "auto", "gpu" or "cpu"; "" reads HAPTICFLUID_BACKEND (unset: auto). Throws
// hf::InvalidArgument naming the setting (or the variable) and the accepted values.
BackendRequest parseBackend(const std::string& backend);

// The names parseBackend accepts, for settings and user interfaces.
inline constexpr const char* kBackendNames[] = {"auto", "gpu", "cpu"};

// Starts a worker on the chosen device. `device_request` is the EGL device (gl/egl_context.h;
// a request other than ""/"auto" makes auto choose the GPU backend, the device the user named);
// `cpu_threads` the CPU backend's threads (0: HAPTICFLUID_CPU_THREADS or one per core).
// Auto's choice and why are in the worker's info().warning when it is not the obvious one.
std::unique_ptr<compute::ComputeWorker> startWorker(const std::string& backend, const std::string& device_request,
                                                    int cpu_threads, std::optional<int> niceness);

}  // namespace hf::session
