// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/device.h"

#include <atomic>

#include "common/error.h"

namespace hf::compute {
namespace {

thread_local Device* t_current = nullptr;
std::atomic<std::uint64_t> g_dispatches{0};
std::atomic<std::uint64_t> g_invocations{0};
std::atomic<std::uint64_t> g_syncs{0};

}  // namespace

const char* backendName(Backend b) { return b == Backend::Cpu ? "cpu" : "gpu"; }

std::size_t texelBytes(TexelFormat format) {
  switch (format) {
    case TexelFormat::R32F: return 4;
    case TexelFormat::RGBA32F: return 16;
    case TexelFormat::R8UI: return 1;
  }
  return 4;
}

Device& currentDevice() {
  if (t_current == nullptr) {
    throw Error("no compute device on this thread: engine objects are made and used on a worker's thread");
  }
  return *t_current;
}

DeviceScope::DeviceScope(Device& device) : previous_(t_current) { t_current = &device; }
DeviceScope::~DeviceScope() { t_current = previous_; }

DispatchCounters dispatchCounters() { return {g_dispatches.load(), g_invocations.load(), g_syncs.load()}; }
void countDispatch(std::uint64_t invocations) {
  g_dispatches.fetch_add(1, std::memory_order_relaxed);
  g_invocations.fetch_add(invocations, std::memory_order_relaxed);
}
void countSync() { g_syncs.fetch_add(1, std::memory_order_relaxed); }

}  // namespace hf::compute
