// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/device_choice.h"

#include <cstdlib>

#include "common/error.h"

namespace hf::gl {

bool isSoftwareRenderer(const std::string& renderer) {
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "SwiftShader", "lavapipe"}) {
    if (renderer.find(name) != std::string::npos) return true;
  }
  return false;
}

std::vector<DeviceDesc> deviceOrder(const std::string& request, const std::vector<DeviceDesc>& devices,
                                    const std::string& listing) {
  std::vector<DeviceDesc> order;
  const DeviceDesc surfaceless{-1, false};
  if (request.empty() || request == "auto" || request == "hardware") {
    for (const auto& d : devices) if (!d.software) order.push_back(d);
    if (request != "hardware") {
      for (const auto& d : devices) if (d.software) order.push_back(d);
    }
    order.push_back(surfaceless);
    return order;
  }
  if (request == "software") {
    for (const auto& d : devices) if (d.software) order.push_back(d);
    order.push_back(DeviceDesc{-1, true});
    return order;
  }
  char* end = nullptr;
  const long index = std::strtol(request.c_str(), &end, 10);
  if (end == request.c_str() || *end != '\0' || index < 0) {
    throw InvalidArgument(std::string("EGL device request '") + request + "' (from " + kEglDeviceEnv +
                          " or the device argument) is not 'auto', 'hardware', 'software' or a device number; "
                          "devices found:\n" + listing);
  }
  for (const auto& d : devices) {
    if (d.index == index) return {d};
  }
  throw InvalidArgument("EGL device " + request + " does not exist (from " + kEglDeviceEnv +
                        " or the device argument); devices found:\n" + listing);
}

DeviceChoice chooseDevice(const std::string& request, const std::vector<DeviceDesc>& devices,
                          const std::string& listing, const std::function<DeviceAttempt(const DeviceDesc&)>& attempt,
                          const std::function<void(const DeviceDesc&)>& discard) {
  const bool is_auto = request.empty() || request == "auto";
  const bool want_hardware = request == "hardware";
  std::string failures;
  for (const DeviceDesc& d : deviceOrder(request, devices, listing)) {
    const std::string label = d.index >= 0 ? "EGL device " + std::to_string(d.index) : "surfaceless platform";
    const DeviceAttempt a = attempt(d);
    if (!a.ok) {
      failures += "  " + label + ": " + a.failure + "\n";
      continue;
    }
    const bool software = d.software || isSoftwareRenderer(a.renderer);
    // auto: a device that says hardware but renders in software is passed over for the next.
    const bool rejected = software && (want_hardware || (is_auto && !d.software && d.index >= 0));
    if (rejected) {
      failures += "  " + label + ": renderer '" + a.renderer + "' is software\n";
      discard(d);
      continue;
    }
    DeviceChoice c{d, a.renderer, software, ""};
    if (is_auto && software) {
      c.warning = "no hardware GPU gave an OpenGL 4.5 context, running on the software renderer '" + a.renderer +
                  "' (slow). Set " + kEglDeviceEnv + "=hardware to fail instead, or =software to choose it"
                  " knowingly." + (failures.empty() ? std::string() : "\n" + failures);
    }
    return c;
  }
  const std::string shown = request.empty() ? std::string("auto") : request;
  throw GlError("EGL context: no device gave an OpenGL 4.5 core context" +
                std::string(want_hardware ? " on a hardware GPU" : "") + " (request '" + shown + "' from " +
                kEglDeviceEnv + " or the device argument):\n" + failures + "devices found:\n" + listing +
                (want_hardware ? "Install the GPU's driver (its EGL vendor library) or unset " +
                                     std::string(kEglDeviceEnv) + " to allow the software renderer."
                               : "Install Mesa's EGL and llvmpipe (packages libegl-mesa0 libgl1-mesa-dri) or a "
                                 "GPU driver."));
}

std::size_t availableMemoryBytes(const MemoryReport& r) {
  constexpr std::size_t kKiB = 1024;
  if (r.nvx_current_available_kb > 0) return static_cast<std::size_t>(r.nvx_current_available_kb) * kKiB;
  if (r.ati_texture_free_kb > 0) return static_cast<std::size_t>(r.ati_texture_free_kb) * kKiB;
  if (r.software && r.host_available_kb > 0) return static_cast<std::size_t>(r.host_available_kb) * kKiB;
  return 0;
}

}  // namespace hf::gl
