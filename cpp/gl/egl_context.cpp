#include "gl/egl_context.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.h"

namespace hf::gl {
namespace {

constexpr const char* kEnvDevice = "HAPTICFLUID_EGL_DEVICE";

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

// Orders the devices to try for a request; throws InvalidArgument for a malformed request.
std::vector<Candidate> candidatesFor(const std::string& request, const std::vector<Candidate>& devices) {
  std::vector<Candidate> order;
  if (request.empty() || request == "auto") {
    for (const auto& d : devices) if (!d.software) order.push_back(d);
    for (const auto& d : devices) if (d.software) order.push_back(d);
    order.push_back(Candidate{});  // surfaceless Mesa as the last resort
    return order;
  }
  if (request == "software") {
    for (const auto& d : devices) if (d.software) order.push_back(d);
    order.push_back(Candidate{EGL_NO_DEVICE_EXT, -1, true});
    return order;
  }
  char* end = nullptr;
  const long index = std::strtol(request.c_str(), &end, 10);
  if (end == request.c_str() || *end != '\0' || index < 0) {
    throw InvalidArgument("EGL device request '" + request + "' (from " + kEnvDevice +
                          " or the device argument) is not 'auto', 'software' or a device number; "
                          "devices found:\n" + listDevices());
  }
  if (index >= static_cast<long>(devices.size())) {
    throw InvalidArgument("EGL device " + request + " does not exist (from " + kEnvDevice +
                          " or the device argument); devices found:\n" + listDevices());
  }
  order.push_back(devices[static_cast<std::size_t>(index)]);
  return order;
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
  constexpr GLenum kNvxTotalAvailableKb = 0x9048;  // GL_GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
  constexpr GLenum kAtiTextureFreeKb = 0x87FC;     // GL_TEXTURE_FREE_MEMORY_ATI
  if (hasGlExtension("GL_NVX_gpu_memory_info")) {
    GLint kb = 0;
    glGetIntegerv(kNvxTotalAvailableKb, &kb);
    return static_cast<std::size_t>(kb) * 1024u;
  }
  if (hasGlExtension("GL_ATI_meminfo")) {
    GLint kb[4] = {0, 0, 0, 0};
    glGetIntegerv(kAtiTextureFreeKb, kb);
    return static_cast<std::size_t>(kb[0]) * 1024u;
  }
  if (software) {
    const long pages = sysconf(_SC_PHYS_PAGES);
    const long page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0) return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
  }
  glGetError();  // an unsupported query above must not leak into the caller's first check
  return 0;
}

}  // namespace

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
    const char* env = std::getenv(kEnvDevice);
    if (env != nullptr) request = env;
  }
  const auto devices = enumerateDevices();
  const auto order = candidatesFor(request, devices);

  std::string failures;
  for (const auto& cand : order) {
    const std::string label = cand.index >= 0 ? "EGL device " + std::to_string(cand.index) : "surfaceless platform";
    EGLDisplay dpy = cand.index >= 0
        ? eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, cand.device, nullptr)
        : eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    auto fail = [&](const std::string& what) {
      failures += "  " + label + ": " + what + " (" + eglErrorText(eglGetError()) + ")\n";
    };
    // Displays are never eglTerminate()d, on failure either: EGL shares one per device in the
    // process, and another simulation (or Blender) may be using it.
    if (dpy == EGL_NO_DISPLAY) { fail("eglGetPlatformDisplay failed"); continue; }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) { fail("eglInitialize failed"); continue; }
    const char* dpy_ext = eglQueryString(dpy, EGL_EXTENSIONS);
    if (!hasToken(dpy_ext, "EGL_KHR_surfaceless_context")) {
      failures += "  " + label + ": no EGL_KHR_surfaceless_context\n";
      continue;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) { fail("eglBindAPI(OpenGL) failed"); continue; }
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasToken(dpy_ext, "EGL_KHR_no_config_context")) {
      const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(dpy, cfg_attr, &config, 1, &n) || n < 1) {
        fail("no OpenGL EGL config"); continue;
      }
    }
    EGLContext ctx = EGL_NO_CONTEXT;
    for (int want_minor : {6, 5}) {
      const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, want_minor,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
      ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attr);
      if (ctx != EGL_NO_CONTEXT) break;
    }
    if (ctx == EGL_NO_CONTEXT) { fail("no OpenGL 4.5 core context"); continue; }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
      fail("eglMakeCurrent failed"); eglDestroyContext(dpy, ctx); continue;
    }
    GLint gl_major = 0, gl_minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &gl_major);
    glGetIntegerv(GL_MINOR_VERSION, &gl_minor);
    if (gl_major < 4 || (gl_major == 4 && gl_minor < 5)) {
      failures += "  " + label + ": OpenGL " + std::to_string(gl_major) + "." + std::to_string(gl_minor) +
                  " only; the engine needs 4.5\n";
      eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(dpy, ctx);
      continue;
    }
    display_ = dpy;
    context_ = ctx;
    info_.renderer = glString(GL_RENDERER);
    info_.vendor = glString(GL_VENDOR);
    info_.version = glString(GL_VERSION);
    const char* egl_vendor = eglQueryString(dpy, EGL_VENDOR);
    info_.egl_vendor = egl_vendor != nullptr ? egl_vendor : "";
    info_.platform = cand.index >= 0 ? "device" : "surfaceless";
    info_.device_index = cand.index;
    info_.software = cand.software || info_.renderer.find("llvmpipe") != std::string::npos ||
                     info_.renderer.find("softpipe") != std::string::npos;
    info_.memory_bytes = queryMemoryBytes(info_.software);
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &info_.max_3d_texture_size);
    glGetError();
    return;
  }
  throw GlError("EGL context: no device gave an OpenGL 4.5 core context (request '" +
                (request.empty() ? std::string("auto") : request) + "'):\n" + failures +
                "Install Mesa's EGL and llvmpipe (packages libegl-mesa0 libgl1-mesa-dri) or a GPU driver.");
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
