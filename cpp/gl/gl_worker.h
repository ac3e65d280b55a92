// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A thread that owns one EGL/GL context and runs GL work posted to it. GL contexts are
// bound to one thread, so every GL call of a simulation goes through its worker.
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>

#include "gl/egl_context.h"

namespace hf::gl {

class GlWorker {
 public:
  // Starts the thread and creates the context on it; rethrows the context's creation error.
  // `niceness` (0..19) makes the thread that much nicer than the caller, and gives the GL driver's
  // own threads (llvmpipe's workers, shared by every context on the device) the same niceness;
  // a refusal is noted in info().warning. Without it (a probe of the device) no thread's priority
  // changes.
  explicit GlWorker(const std::string& device_request = "", std::optional<int> niceness = std::nullopt);
  // Runs the queued work, destroys the context on its thread, then joins.
  ~GlWorker();
  GlWorker(const GlWorker&) = delete;
  GlWorker& operator=(const GlWorker&) = delete;

  const ContextInfo& info() const { return info_; }

  // Runs fn on the GL thread and waits for it; its result is returned, its exception rethrown.
  template <class F>
  auto call(F&& fn) -> std::invoke_result_t<F> {
    using R = std::invoke_result_t<F>;
    auto task = std::make_shared<std::packaged_task<R()>>(std::forward<F>(fn));
    std::future<R> result = task->get_future();
    post([task] { (*task)(); });
    return result.get();
  }

 private:
  void post(std::function<void()> job);
  void loop(const std::string& device_request, std::optional<int> niceness, std::promise<void>& ready);

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  ContextInfo info_;
};

}  // namespace hf::gl
