// SPDX-License-Identifier: GPL-3.0-or-later
// The EGL device choice and the free-memory figure as pure functions over device descriptions
// (gl/device_choice.h), and the "hardware" request failing clearly on a machine without a GPU.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "gl/device_choice.h"
#include "gl/gl_device.h"
#include "test_util.h"

namespace hf::gl {
using namespace hf::compute;  // the device interface these GL tests exercise
namespace {

using hf::test::contains;
using hf::test::EnvGuard;

std::vector<int> indices(const std::vector<DeviceDesc>& order) {
  std::vector<int> out;
  for (const auto& d : order) out.push_back(d.index);
  return out;
}

// A machine: device 0 says hardware (a GPU), 1 says software (llvmpipe), 2 says hardware.
const std::vector<DeviceDesc> kMachine = {{0, false}, {1, true}, {2, false}};

TEST(GlDeviceChoice, OrderPerRequest) {
  EXPECT_EQ(indices(deviceOrder("", kMachine, "")), (std::vector<int>{0, 2, 1, -1}));
  EXPECT_EQ(indices(deviceOrder("auto", kMachine, "")), (std::vector<int>{0, 2, 1, -1}));
  EXPECT_EQ(indices(deviceOrder("hardware", kMachine, "")), (std::vector<int>{0, 2, -1}));
  EXPECT_EQ(indices(deviceOrder("software", kMachine, "")), (std::vector<int>{1, -1}));
  EXPECT_EQ(indices(deviceOrder("2", kMachine, "")), (std::vector<int>{2}));
  EXPECT_THROW(deviceOrder("3", kMachine, ""), InvalidArgument);
  EXPECT_THROW(deviceOrder("gpu", kMachine, ""), InvalidArgument);
}

TEST(GlDeviceChoice, SoftwareRenderersAreRecognised) {
  EXPECT_TRUE(isSoftwareRenderer("llvmpipe (LLVM 15.0.6, 256 bits)"));
  EXPECT_TRUE(isSoftwareRenderer("softpipe"));
  EXPECT_TRUE(isSoftwareRenderer("virgl (llvmpipe (LLVM 12.0.0, 256 bits))"));  // a VM without a host GPU
  EXPECT_FALSE(isSoftwareRenderer("NVIDIA GeForce RTX 4090/PCIe/SSE2"));
  EXPECT_FALSE(isSoftwareRenderer("AMD Radeon RX 7900 XTX (radeonsi, navi31, LLVM 15.0.7)"));
  EXPECT_FALSE(isSoftwareRenderer("virgl (NVIDIA GeForce RTX 3080)"));
}

// Runs chooseDevice over fake attempts: `renderers` maps a device index to its GL_RENDERER
// ("" = making the context fails). Records which were tried and which discarded.
struct Fake {
  explicit Fake(std::map<int, std::string> r = {}) : renderers(std::move(r)) {}
  std::map<int, std::string> renderers;
  std::vector<int> tried, discarded;
  DeviceChoice choose(const std::string& request, const std::vector<DeviceDesc>& devices) {
    return chooseDevice(
        request, devices, "  (listing)\n",
        [&](const DeviceDesc& d) {
          tried.push_back(d.index);
          const std::string r = renderers.count(d.index) ? renderers.at(d.index) : "";
          return r.empty() ? DeviceAttempt{false, "", "no context"} : DeviceAttempt{true, r, ""};
        },
        [&](const DeviceDesc& d) { discarded.push_back(d.index); });
  }
};

TEST(GlDeviceChoice, AutoTakesTheFirstHardwareRendererWithoutWarning) {
  Fake f{{{0, "NVIDIA H200/PCIe/SSE2"}, {1, "llvmpipe"}, {2, "AMD Radeon"}, {-1, "llvmpipe"}}};
  const DeviceChoice c = f.choose("auto", kMachine);
  EXPECT_EQ(c.device.index, 0);
  EXPECT_FALSE(c.software);
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  EXPECT_EQ(f.tried, (std::vector<int>{0}));
}

TEST(GlDeviceChoice, AutoPassesOverAHardwareDeviceThatRendersInSoftware) {
  // Device 0 is virgl without a host GPU: its renderer is llvmpipe; device 2 is a real GPU.
  Fake f{{{0, "virgl (llvmpipe (LLVM 15))"}, {1, "llvmpipe"}, {2, "AMD Radeon"}, {-1, "llvmpipe"}}};
  const DeviceChoice c = f.choose("", kMachine);
  EXPECT_EQ(c.device.index, 2);
  EXPECT_EQ(f.tried, (std::vector<int>{0, 2}));
  EXPECT_EQ(f.discarded, (std::vector<int>{0}));  // its context was released
  EXPECT_TRUE(c.warning.empty());
}

TEST(GlDeviceChoice, AutoEndingOnSoftwareWarnsAndSaysWhy) {
  // The device platform of the GPU fails (e.g. no config), the other renders in software.
  Fake f{{{1, "llvmpipe (LLVM 15)"}, {2, "virgl (llvmpipe)"}, {-1, "llvmpipe"}}};
  const DeviceChoice c = f.choose("auto", kMachine);
  EXPECT_EQ(c.device.index, 1);
  EXPECT_TRUE(c.software);
  EXPECT_TRUE(contains(c.warning, "software renderer 'llvmpipe (LLVM 15)'")) << c.warning;
  EXPECT_TRUE(contains(c.warning, std::string(kEglDeviceEnv) + "=hardware")) << c.warning;
  EXPECT_TRUE(contains(c.warning, "EGL device 0: no context")) << c.warning;
  EXPECT_TRUE(contains(c.warning, "EGL device 2: renderer 'virgl (llvmpipe)' is software")) << c.warning;
}

TEST(GlDeviceChoice, ExplicitSoftwareDoesNotWarn) {
  Fake f{{{1, "llvmpipe"}, {-1, "llvmpipe"}}};
  const DeviceChoice c = f.choose("software", kMachine);
  EXPECT_EQ(c.device.index, 1);
  EXPECT_TRUE(c.software);
  EXPECT_TRUE(c.warning.empty());
}

TEST(GlDeviceChoice, HardwareAcceptsOnlyAGpuAndOtherwiseThrowsNamingEachDevice) {
  Fake gpu{{{0, "llvmpipe"}, {2, "NVIDIA H200"}}};
  EXPECT_EQ(gpu.choose("hardware", kMachine).device.index, 2);

  Fake none{{{0, "virgl (llvmpipe)"}, {1, "llvmpipe"}, {-1, "llvmpipe"}}};
  try {
    none.choose("hardware", kMachine);
    FAIL() << "a software renderer was accepted for 'hardware'";
  } catch (const GlError& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, "on a hardware GPU")) << msg;
    EXPECT_TRUE(contains(msg, "EGL device 0: renderer 'virgl (llvmpipe)' is software")) << msg;
    EXPECT_TRUE(contains(msg, "EGL device 2: no context")) << msg;
    EXPECT_TRUE(contains(msg, "surfaceless platform: renderer 'llvmpipe' is software")) << msg;
    EXPECT_TRUE(contains(msg, "(listing)")) << msg;
  }
  EXPECT_EQ(none.tried, (std::vector<int>{0, 2, -1}));  // the software device 1 is never tried
  EXPECT_EQ(none.discarded, (std::vector<int>{0, -1}));
}

TEST(GlDeviceChoice, NumberedDeviceIsTakenAsItIs) {
  Fake f{{{2, "llvmpipe"}}};
  const DeviceChoice c = f.choose("2", kMachine);
  EXPECT_EQ(c.device.index, 2);
  EXPECT_TRUE(c.software);
  EXPECT_TRUE(c.warning.empty());
  Fake fails{};
  EXPECT_THROW(fails.choose("2", kMachine), GlError);
}

TEST(GlDeviceChoice, AvailableMemoryIsWhatIsFreeNow) {
  MemoryReport nv;
  nv.nvx_current_available_kb = 3 * 1024 * 1024;
  nv.ati_texture_free_kb = 5;
  EXPECT_EQ(availableMemoryBytes(nv), std::size_t{3} << 30);
  MemoryReport ati;
  ati.ati_texture_free_kb = 1024;
  ati.host_available_kb = 99;
  EXPECT_EQ(availableMemoryBytes(ati), std::size_t{1} << 20);
  MemoryReport soft;
  soft.software = true;
  soft.host_available_kb = 2048;
  EXPECT_EQ(availableMemoryBytes(soft), std::size_t{2} << 20);
  MemoryReport gpu_unknown;  // a GPU without either extension: unknown, the host's RAM says nothing
  gpu_unknown.host_available_kb = 2048;
  EXPECT_EQ(availableMemoryBytes(gpu_unknown), 0u);
}

TEST(GlDeviceChoice, HardwareRequestFailsClearlyWithoutAGpu) {
  EnvGuard env(kEglDeviceEnv, nullptr);
  GlWorker probe("auto");
  if (!probe.info().software) GTEST_SKIP() << "this machine has a GPU: " << probe.info().renderer;
  EXPECT_TRUE(contains(probe.info().warning, "software renderer")) << probe.info().warning;
  try {
    GlWorker worker("hardware");
    FAIL() << "'hardware' was accepted on " << worker.info().renderer;
  } catch (const GlError& e) {
    EXPECT_TRUE(contains(e.what(), "on a hardware GPU")) << e.what();
    EXPECT_TRUE(contains(e.what(), "devices found")) << e.what();
  }
  EnvGuard hw(kEglDeviceEnv, "hardware");
  EXPECT_THROW(GlWorker{}, GlError);
}

}  // namespace
}  // namespace hf::gl
