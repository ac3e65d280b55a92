// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A thread that owns one compute device and runs work posted to it with the device current: a
// GL context belongs to the thread that made it, so every engine call of a simulation goes
// through its worker (the CPU device keeps the same rule, so both behave alike).
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

#include "compute/device.h"

namespace hf::compute {

class ComputeWorker {
 public:
  // Starts the thread and runs `make_device` on it (it may also set the thread's name and
  // priority); rethrows its exception.
  explicit ComputeWorker(std::function<std::unique_ptr<Device>()> make_device);
  // Runs the queued work, destroys the device on its thread, then joins.
  ~ComputeWorker();
  ComputeWorker(const ComputeWorker&) = delete;
  ComputeWorker& operator=(const ComputeWorker&) = delete;

  const DeviceInfo& info() const { return info_; }

  // Runs fn on the worker's thread and waits for it; its result is returned, its exception rethrown.
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
  void loop(const std::function<std::unique_ptr<Device>()>& make_device, std::promise<void>& ready);

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  DeviceInfo info_;
};

}  // namespace hf::compute
