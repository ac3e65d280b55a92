// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The CPU device's threads: the calling thread and threads - 1 persistent workers that split
// each dispatch's range into contiguous chunks. Workers spin briefly for the next dispatch of a
// step (a step is hundreds of back-to-back dispatches) and then sleep, so an idle simulation
// costs no CPU. Workers are started by the thread that makes the pool and inherit its niceness
// (common/thread_priority.h), so the simulation's CPU share applies to all of them.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace hf::cpu {

class ThreadPool {
 public:
  explicit ThreadPool(int threads);  // threads >= 1
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return threads_; }

  // Calls fn(begin, end) over contiguous chunks that cover [0, n) once, one chunk per thread at
  // most, and returns when all are done. How the range is cut depends on threads(): callers
  // must not make results depend on it (the kernels write disjoint outputs, and reductions sum
  // fixed rows). An exception from fn is rethrown here (the first one).
  template <class F>
  void parallelFor(int n, F&& fn) {
    if (n <= 0) return;
    using Fn = std::remove_reference_t<F>;
    auto call = [](void* ctx, int begin, int end) { (*static_cast<Fn*>(ctx))(begin, end); };
    run(n, call, const_cast<void*>(static_cast<const void*>(&fn)));
  }

 private:
  using Call = void (*)(void*, int, int);
  void run(int n, Call call, void* ctx);
  void work(int index);
  void runChunk(int chunk);

  int threads_;
  std::vector<std::thread> workers_;
  // The job in flight.
  Call call_ = nullptr;
  void* ctx_ = nullptr;
  int n_ = 0;
  int chunks_ = 0;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<int> pending_{0};
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  bool stopping_ = false;
};

}  // namespace hf::cpu
