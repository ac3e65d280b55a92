// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The one place that creates and frees the headless EGL + OpenGL 4.5 core context.
#include <cstddef>
#include <string>

namespace hf::gl {

// What the context runs on, as reported to the user.
struct ContextInfo {
  std::string renderer;      // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string vendor;        // GL_VENDOR
  std::string version;       // GL_VERSION
  std::string egl_vendor;    // EGL_VENDOR of the display
  std::string platform;      // "device" (EGL_EXT_platform_device) or "surfaceless"
  int device_index = -1;     // index in eglQueryDevicesEXT's list; -1 for the surfaceless platform
  bool software = false;     // true for Mesa llvmpipe / softpipe
  std::size_t memory_bytes = 0;  // GPU memory free when the context was made (the host's
                                 // MemAvailable for a software device); 0 = unknown
  int max_3d_texture_size = 0;   // GL_MAX_3D_TEXTURE_SIZE, cells per axis
  std::size_t max_storage_block_bytes = 0;  // GL_MAX_SHADER_STORAGE_BLOCK_SIZE (>= 128 MiB by GL 4.3)
  std::string warning;           // "" or why this device may not be what the user wants
};

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

// One line per EGL device: "<index>: <hardware|software> <extensions/drm node>".
std::string listDevices();

}  // namespace hf::gl
