// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The GL device (compute::Device on an EGL context) and a worker that owns one. GL contexts
// are bound to one thread, so every GL call of a simulation goes through its worker.
#include <memory>
#include <optional>
#include <string>

#include "compute/compute_worker.h"
#include "compute/device.h"

namespace hf::gl {

// Makes the context (egl_context.h: `device_request` chooses the EGL device) on the calling
// thread, which becomes the device's thread. `niceness` (0..19) makes the thread that much
// nicer than it was, and gives the GL driver's own threads (llvmpipe's workers, shared by every
// context on the device) the same niceness; a refusal is noted in info().warning. Without it (a
// probe of the device) no thread's priority changes.
std::unique_ptr<compute::Device> makeGlDevice(const std::string& device_request, std::optional<int> niceness);

// A worker thread with a GL device.
class GlWorker : public compute::ComputeWorker {
 public:
  explicit GlWorker(const std::string& device_request = "", std::optional<int> niceness = std::nullopt)
      : ComputeWorker([device_request, niceness] { return makeGlDevice(device_request, niceness); }) {}
};

}  // namespace hf::gl
