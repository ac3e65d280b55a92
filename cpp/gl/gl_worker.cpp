// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_worker.h"

#include <algorithm>
#include <set>

#include "common/thread_priority.h"

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

}  // namespace

GlWorker::GlWorker(const std::string& device_request, std::optional<int> niceness) {
  std::promise<void> ready;
  std::future<void> started = ready.get_future();
  thread_ = std::thread([this, device_request, niceness, &ready] { loop(device_request, niceness, ready); });
  try {
    started.get();
  } catch (...) {
    thread_.join();
    throw;
  }
}

GlWorker::~GlWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void GlWorker::post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    jobs_.push_back(std::move(job));
  }
  wake_.notify_one();
}

void GlWorker::loop(const std::string& device_request, std::optional<int> niceness, std::promise<void>& ready) {
  std::string refused = lowerCurrentThreadPriority(niceness.value_or(0));
#if defined(__linux__)
  nameCurrentThread(kWorkerName);
  const std::vector<int> before = threadIds();
#endif
  std::unique_ptr<EglContext> context;
  try {
    context = std::make_unique<EglContext>(device_request);
    info_ = context->info();
#if defined(__linux__)
    noteDriverThreads(before);
    if (refused.empty() && niceness) refused = matchDriverThreads();
#endif
    if (!refused.empty()) {
      info_.warning += (info_.warning.empty() ? "" : "; ") + ("thread priority: " + refused);
    }
  } catch (...) {
    ready.set_exception(std::current_exception());
    return;
  }
  ready.set_value();
  for (;;) {
    std::function<void()> job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) break;  // stopping, and nothing left to run
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job();  // packaged_task stores any exception for the caller
  }
}

}  // namespace hf::gl
