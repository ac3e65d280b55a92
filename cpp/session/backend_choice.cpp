// SPDX-License-Identifier: GPL-3.0-or-later
#include "session/backend_choice.h"

#include <cstdlib>

#include "common/error.h"
#include "common/log_sink.h"
#include "cpu/cpu_device.h"
#include "gl/device_choice.h"
#include "gl/egl_context.h"
#include "gl/gl_device.h"

namespace hf::session {
namespace {

BackendRequest parseName(const std::string& name, const std::string& from) {
  if (name == "auto") return BackendRequest::Auto;
  if (name == "gpu") return BackendRequest::Gpu;
  if (name == "cpu") return BackendRequest::Cpu;
  throw InvalidArgument(from + " must be 'auto', 'gpu' or 'cpu', got '" + name + "'");
}

// The EGL device request as the GL device will read it (argument, else the environment).
std::string effectiveDeviceRequest(const std::string& device_request) {
  if (!device_request.empty()) return device_request;
  const char* env = std::getenv(gl::kEglDeviceEnv);
  return env != nullptr ? env : "";
}

}  // namespace

BackendRequest parseBackend(const std::string& backend) {
  if (!backend.empty()) return parseName(backend, "backend");
  const char* env = std::getenv(kBackendEnv);
  if (env == nullptr || *env == '\0') return BackendRequest::Auto;
  return parseName(env, kBackendEnv);
}

std::unique_ptr<compute::ComputeWorker> startWorker(const std::string& backend, const std::string& device_request,
                                                    int cpu_threads, std::optional<int> niceness) {
  const BackendRequest request = parseBackend(backend);
  const int threads = cpu::resolveThreads(cpu_threads);  // checked before any device is made
  auto cpuWorker = [&] {
    return std::make_unique<compute::ComputeWorker>([threads, niceness] { return cpu::makeCpuDevice(threads, niceness); });
  };
  auto glWorker = [&](const std::string& gl_request) {
    return std::make_unique<compute::ComputeWorker>(
        [gl_request, niceness] { return gl::makeGlDevice(gl_request, niceness); });
  };
  if (request == BackendRequest::Cpu) return cpuWorker();
  if (request == BackendRequest::Gpu) return glWorker(device_request);
  // Auto: a named EGL device means the user chose the GPU backend's device.
  const std::string named = effectiveDeviceRequest(device_request);
  if (!named.empty() && named != "auto") return glWorker(device_request);
  if (!gl::hasHardwareEglDevice()) return cpuWorker();
  try {
    return glWorker("hardware");
  } catch (const Error& e) {
    auto worker = cpuWorker();
    log::info("hapticfluid.device", std::string("backend auto: no hardware GPU gave a context, running on the CPU "
                                                 "backend (") + e.what() + ")");
    return worker;
  }
}

}  // namespace hf::session
