// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The one place that creates and frees the headless EGL + OpenGL 4.5 core context.
#include <cstddef>
#include <string>

#include "compute/device.h"

namespace hf::gl {

using ContextInfo = compute::DeviceInfo;  // what the context runs on (backend Gpu)

// Owns an EGLDisplay + EGLContext and makes it current on the constructing thread. Not
// copyable or movable: the context belongs to the thread that made it.
//
// Device choice (`request`, or the environment variable HAPTICFLUID_EGL_DEVICE when
// `request` is empty):
//   ""/"auto"  first hardware EGL device whose renderer is a GPU, else software (with a
//              warning in info().warning, which Python callers log; nothing is printed)
//   "hardware" a hardware GPU or an hf::GlError
//   "software" Mesa's software rasterizer (llvmpipe)
//   "<N>"      EGL device number N (as listed by listDevices())
// The choice itself is gl/device_choice.h's chooseDevice().
class EglContext {
 public:
  explicit EglContext(const std::string& request = "");
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  const ContextInfo& info() const { return info_; }

 private:
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  ContextInfo info_;
};

// True when an enumerated EGL device says it is hardware (no EGL_MESA_device_software): a GPU
// may be there (a VM's virgl says so too; only a context tells). Makes no context.
bool hasHardwareEglDevice();

// One line per EGL device: "<index>: <hardware|software> <extensions/drm node>".
std::string listDevices();

}  // namespace hf::gl
