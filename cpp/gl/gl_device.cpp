// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_device.h"

#include <algorithm>
#include <set>

#include "common/thread_priority.h"
#include "gl/egl_context.h"
#include "gl/gl_buffer.h"
#include "gl/gl_program.h"
#include "gl/gl_stage_timer.h"
#include "gl/gl_texture.h"

namespace hf::gl {

namespace {

#if defined(__linux__)
// The GL driver's own worker threads (llvmpipe's rasterizer and compute pools): started while a
// GL worker made the process's first context on a display, and shared from then on by every
// context on it (displays are never terminated). A new thread seen across a context's creation
// is the driver's when it carries the worker's name (inherited) or llvmpipe's; Blender's threads
// (its own GL's llvmpipe threads started long before) never match.
constexpr const char* kWorkerName = "hf-gl";
std::mutex g_driver_threads_mutex;
std::set<int> g_driver_threads;

void noteDriverThreads(const std::vector<int>& before) {
  std::lock_guard<std::mutex> lock(g_driver_threads_mutex);
  for (int tid : threadIds()) {
    if (std::find(before.begin(), before.end(), tid) != before.end() || tid == currentThreadId()) continue;
    const std::string name = threadName(tid);
    if (name.rfind(kWorkerName, 0) == 0 || name.rfind("llvmpipe", 0) == 0) g_driver_threads.insert(tid);
  }
}

// Gives the driver's threads this thread's niceness: they run this worker's GL work. They are
// shared by every context on the display, so they follow the simulation made last. Making them
// nicer needs no privilege; making them less nice again (a simulation at 0 after one at 10) needs
// CAP_SYS_NICE: without it they keep the earlier niceness, and the reason is returned.
std::string matchDriverThreads() {
  const int niceness = threadNiceness(currentThreadId());
  std::lock_guard<std::mutex> lock(g_driver_threads_mutex);
  const std::vector<int> alive = threadIds();
  std::string refused;
  for (auto it = g_driver_threads.begin(); it != g_driver_threads.end();) {
    if (std::find(alive.begin(), alive.end(), *it) == alive.end()) {
      it = g_driver_threads.erase(it);
      continue;
    }
    const int was = threadNiceness(*it);
    if (was != niceness && refused.empty()) {
      const std::string why = setThreadNiceness(*it, niceness);
      if (!why.empty()) {
        refused = "the GL driver's threads keep niceness " + std::to_string(was) + " from an earlier simulation (" +
                  why + ")";
      }
    }
    ++it;
  }
  return refused;
}
#endif

class GlDevice final : public compute::Device {
 public:
  explicit GlDevice(const std::string& request) : context_(request), info_(context_.info()) {}
  const compute::DeviceInfo& info() const override { return info_; }
  compute::DeviceInfo& mutableInfo() { return info_; }
  std::unique_ptr<compute::TextureImpl> makeTexture(const glm::ivec3& size, compute::TexelFormat format,
                                                    const std::string& label) override {
    return std::make_unique<GlTexture>(size, format, label);
  }
  std::unique_ptr<compute::BufferImpl> makeBuffer(std::size_t bytes, const std::string& label) override {
    return std::make_unique<GlBuffer>(bytes, label);
  }
  std::unique_ptr<compute::ProgramImpl> makeProgram(const std::string& file, const compute::Defines& defines) override {
    return std::make_unique<GlProgram>(file, defines);
  }
  std::unique_ptr<compute::TimerImpl> makeTimer() override { return std::make_unique<GlStageTimer>(); }

 private:
  EglContext context_;
  compute::DeviceInfo info_;
};

}  // namespace

std::unique_ptr<compute::Device> makeGlDevice(const std::string& device_request, std::optional<int> niceness) {
  std::string refused = lowerCurrentThreadPriority(niceness.value_or(0));
#if defined(__linux__)
  nameCurrentThread(kWorkerName);
  const std::vector<int> before = threadIds();
#endif
  auto device = std::make_unique<GlDevice>(device_request);
  compute::DeviceInfo& info = device->mutableInfo();
#if defined(__linux__)
  noteDriverThreads(before);
  if (refused.empty() && niceness) refused = matchDriverThreads();
#endif
  if (!refused.empty()) {
    info.warning += (info.warning.empty() ? "" : "; ") + ("thread priority: " + refused);
  }
  return device;
}

}  // namespace hf::gl
