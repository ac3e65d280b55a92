// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Which EGL device the context is made on, and how much GPU memory counts as free: the
// decisions, as pure functions over descriptions, apart from the EGL/GL calls that feed them
// (egl_context.cpp), so they can be tested without the hardware they are about.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace hf::gl {

// The environment variable that chooses the device when no device argument is given.
inline constexpr const char* kEglDeviceEnv = "HAPTICFLUID_EGL_DEVICE";

// One place a context can be made: an enumerated EGL device (index >= 0) or Mesa's
// surfaceless platform (index -1, tried last).
struct DeviceDesc {
  int index = -1;
  bool software = false;  // the device says so (EGL_MESA_device_software)
};

// What making a 4.5 core context on a device gave: the GL_RENDERER, or why it failed.
struct DeviceAttempt {
  bool ok = false;
  std::string renderer;  // GL_RENDERER when ok
  std::string failure;   // the reason when not ok
};

struct DeviceChoice {
  DeviceDesc device;
  std::string renderer;
  bool software = false;  // the renderer is a software rasterizer
  std::string warning;    // "" or why the user may not want this device (auto ending on software)
};

// True for renderers that run on the CPU: Mesa llvmpipe / softpipe / swrast, and virgl or
// venus without a host GPU behind them (their renderer names the host's llvmpipe).
bool isSoftwareRenderer(const std::string& renderer);

// The order devices are tried in for `request`:
//   ""/"auto"   devices that say hardware, then software ones, then surfaceless Mesa
//   "hardware"  devices that say hardware, then surfaceless Mesa (accepted only on a GPU)
//   "software"  devices that say software, then surfaceless Mesa
//   "<N>"       device N alone
// Throws hf::InvalidArgument for a malformed request or a device number not in `devices`;
// `listing` (listDevices()) goes into that message.
std::vector<DeviceDesc> deviceOrder(const std::string& request, const std::vector<DeviceDesc>& devices,
                                    const std::string& listing);

// Tries the devices in deviceOrder() with `attempt` and keeps the first acceptable one:
// "auto" passes over a device that says hardware but whose renderer is software (a VM's
// virgl without a host GPU) and tries the next one, and warns when it ends on software;
// "hardware" accepts only a hardware renderer and throws hf::GlError otherwise. `discard`
// releases a context that was made but not accepted. Throws hf::GlError when nothing is accepted.
DeviceChoice chooseDevice(const std::string& request, const std::vector<DeviceDesc>& devices,
                          const std::string& listing, const std::function<DeviceAttempt(const DeviceDesc&)>& attempt,
                          const std::function<void(const DeviceDesc&)>& discard);

// What the driver tells about memory, in KiB (0 = not reported), and the host's MemAvailable.
struct MemoryReport {
  long long nvx_current_available_kb = 0;  // GL_NVX_gpu_memory_info: what is free now
  long long ati_texture_free_kb = 0;       // GL_ATI_meminfo: free texture memory now
  long long host_available_kb = 0;         // /proc/meminfo MemAvailable
  bool software = false;                   // the renderer runs on the CPU
};

// Bytes a new simulation may count on: what is free now, not the device's total (a shared GPU
// would over-admit). NVX current available, else ATI free, else for a software device the
// host's MemAvailable; 0 when unknown.
std::size_t availableMemoryBytes(const MemoryReport& r);

}  // namespace hf::gl
