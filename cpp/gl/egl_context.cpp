// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/host_memory.h"
#include "common/log_sink.h"
#include "gl/device_choice.h"
#include "gl/gl_check.h"

namespace hf::gl {
namespace {

struct Candidate {
  EGLDeviceEXT device = EGL_NO_DEVICE_EXT;  // EGL_NO_DEVICE_EXT = surfaceless platform
  int index = -1;
  bool software = false;
};

bool hasToken(const char* list, const char* token) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(token);
  for (const char* p = list; (p = std::strstr(p, token)) != nullptr; p += n) {
    const bool start_ok = (p == list) || p[-1] == ' ';
    const bool end_ok = p[n] == '\0' || p[n] == ' ';
    if (start_ok && end_ok) return true;
  }
  return false;
}

std::string eglErrorText(EGLint code) {
  switch (code) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error " + std::to_string(code);
  }
}

std::vector<Candidate> enumerateDevices() {
  std::vector<Candidate> out;
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!hasToken(client_ext, "EGL_EXT_device_enumeration") && !hasToken(client_ext, "EGL_EXT_device_base")) {
    return out;
  }
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  if (query_devices == nullptr || query_string == nullptr) return out;
  EGLint count = 0;
  if (!query_devices(0, nullptr, &count) || count <= 0) return out;
  std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
  if (!query_devices(count, devices.data(), &count)) return out;
  for (EGLint i = 0; i < count; ++i) {
    const char* ext = query_string(devices[static_cast<std::size_t>(i)], EGL_EXTENSIONS);
    out.push_back({devices[static_cast<std::size_t>(i)], i, hasToken(ext, "EGL_MESA_device_software")});
  }
  return out;
}

std::string glString(GLenum name) {
  const auto* s = reinterpret_cast<const char*>(glGetString(name));
  return s != nullptr ? s : "";
}

bool hasGlExtension(const char* name) {
  GLint n = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i) {
    const auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e != nullptr && std::strcmp(e, name) == 0) return true;
  }
  return false;
}

std::size_t queryMemoryBytes(bool software) {
  constexpr GLenum kNvxCurrentAvailableKb = 0x9049;  // GL_GPU_MEMORY_INFO_CURRENT_AVAILABLE_VIDMEM_NVX
  constexpr GLenum kAtiTextureFreeKb = 0x87FC;       // GL_TEXTURE_FREE_MEMORY_ATI
  MemoryReport r;
  r.software = software;
  if (hasGlExtension("GL_NVX_gpu_memory_info")) {
    GLint kb = 0;
    glGetIntegerv(kNvxCurrentAvailableKb, &kb);
    r.nvx_current_available_kb = kb;
  }
  if (hasGlExtension("GL_ATI_meminfo")) {
    GLint kb[4] = {0, 0, 0, 0};
    glGetIntegerv(kAtiTextureFreeKb, kb);
    r.ati_texture_free_kb = kb[0];
  }
  if (software) r.host_available_kb = hostAvailableKb();
  glGetError();  // an unsupported query above must not leak into the caller's first check
  return availableMemoryBytes(r);
}

}  // namespace

bool hasHardwareEglDevice() {
  for (const Candidate& c : enumerateDevices()) {
    if (!c.software) return true;
  }
  return false;
}

std::string listDevices() {
  std::string out;
  auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
  for (const auto& d : enumerateDevices()) {
    out += "  " + std::to_string(d.index) + ": " + (d.software ? "software" : "hardware");
    const char* ext = query_string != nullptr ? query_string(d.device, EGL_EXTENSIONS) : nullptr;
    if (hasToken(ext, "EGL_EXT_device_drm")) {
      const char* node = query_string(d.device, EGL_DRM_DEVICE_FILE_EXT);
      if (node != nullptr) out += std::string(" ") + node;
    }
    out += "\n";
  }
  if (out.empty()) out = "  (no EGL devices enumerated; the surfaceless Mesa platform is used)\n";
  return out;
}

EglContext::EglContext(const std::string& request_arg) {
  std::string request = request_arg;
  if (request.empty()) {
    const char* env = std::getenv(kEglDeviceEnv);
    if (env != nullptr) request = env;
  }
  const auto found = enumerateDevices();
  std::vector<DeviceDesc> devices;
  for (const auto& c : found) devices.push_back({c.index, c.software});
  EGLDisplay dpy = EGL_NO_DISPLAY;
  EGLContext ctx = EGL_NO_CONTEXT;
  auto attempt = [&](const DeviceDesc& d) -> DeviceAttempt {
    dpy = d.index >= 0
        ? eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, found[static_cast<std::size_t>(d.index)].device, nullptr)
        : eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    auto fail = [](const std::string& what) {
      return DeviceAttempt{false, "", what + " (" + eglErrorText(eglGetError()) + ")"};
    };
    // Displays are never eglTerminate()d, on failure either: EGL shares one per device in the
    // process, and another simulation (or Blender) may be using it.
    if (dpy == EGL_NO_DISPLAY) return fail("eglGetPlatformDisplay failed");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) return fail("eglInitialize failed");
    const char* dpy_ext = eglQueryString(dpy, EGL_EXTENSIONS);
    if (!hasToken(dpy_ext, "EGL_KHR_surfaceless_context")) return {false, "", "no EGL_KHR_surfaceless_context"};
    if (!eglBindAPI(EGL_OPENGL_API)) return fail("eglBindAPI(OpenGL) failed");
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasToken(dpy_ext, "EGL_KHR_no_config_context")) {
      // Without EGL_SURFACE_TYPE the default (EGL_WINDOW_BIT) matches no config of the device
      // platform, which has no windows; the context is used surfaceless anyway.
      const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_DONT_CARE, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(dpy, cfg_attr, &config, 1, &n) || n < 1) return fail("no OpenGL EGL config");
    }
    ctx = EGL_NO_CONTEXT;
    // The debug attribute (EGL 1.5) only in the debug mode: an EGL 1.4 driver rejects it.
    const EGLint debug_name = debugMode() ? EGL_CONTEXT_OPENGL_DEBUG : EGL_NONE;
    for (int want_minor : {6, 5}) {
      const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, want_minor,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 debug_name, EGL_TRUE, EGL_NONE};
      ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attr);
      if (ctx != EGL_NO_CONTEXT) break;
    }
    if (ctx == EGL_NO_CONTEXT) return fail("no OpenGL 4.5 core context");
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      DeviceAttempt a = fail("eglMakeCurrent failed");
      eglDestroyContext(dpy, ctx);
      return a;
    }
    GLint gl_major = 0, gl_minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
    glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
    if (gl_major < 4 || (gl_major == 4 && gl_minor < 5)) {
      eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(dpy, ctx);
      return {false, "", "OpenGL " + std::to_string(gl_major) + "." + std::to_string(gl_minor) +
                             " only; the engine needs 4.5"};
    }
    return {true, glString(GL_RENDERER), ""};
  };
  auto discard = [&](const DeviceDesc&) {
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
  };
  const DeviceChoice choice = chooseDevice(request, devices, listDevices(), attempt, discard);
  display_ = dpy;
  context_ = ctx;
  info_.renderer = choice.renderer;
  info_.vendor = glString(GL_VENDOR);
  info_.version = glString(GL_VERSION);
  const char* egl_vendor = eglQueryString(dpy, EGL_VENDOR);
  info_.egl_vendor = egl_vendor != nullptr ? egl_vendor : "";
  info_.platform = choice.device.index >= 0 ? "device" : "surfaceless";
  info_.device_index = choice.device.index;
  info_.software = choice.software;
  info_.warning = choice.warning;
  // Info, not a warning: the software renderer is the expected device on a machine with no GPU.
  if (!info_.warning.empty()) log::info("hapticfluid.gl", info_.warning);
  info_.memory_bytes = queryMemoryBytes(info_.software);
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info_.max_3d_texture_size);
  GLint ssbo_block = 0;
  glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &ssbo_block);
  info_.max_storage_block_bytes = static_cast<std::size_t>(ssbo_block > 0 ? ssbo_block : 0);
  glGetError();
  if (debugMode()) installDebugOutput();
}

EglContext::~EglContext() {
  if (display_ != nullptr) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != nullptr) eglDestroyContext(display_, context_);
    eglReleaseThread();
    // The display is not terminated: EGL displays are shared per process, and another
    // context (a second simulation, or Blender's) may still use the same one.
  }
}

}  // namespace hf::gl
