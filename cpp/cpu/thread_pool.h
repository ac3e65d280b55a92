// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The CPU device's threads: the calling thread and threads - 1 persistent workers that share
// each dispatch's range, cut into a few contiguous chunks per thread that each thread claims one
// after the other. A thread the OS has not run yet (the bake's writer or Blender's drawing has
// the core) then delays nothing: the threads that run take its chunks, and the dispatch ends
// when every chunk is done, not when every thread has come. Workers spin for up to a millisecond
// for the next dispatch of a step (a step is hundreds of back-to-back dispatches, some apart by a
// coarse level's work on the calling thread) and then sleep, so an idle simulation costs no CPU.
// Workers are started by the thread that makes the pool and inherit its niceness
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

  // Calls fn(begin, end) over contiguous chunks that cover [0, n) once (at most
  // kChunksPerThread per thread, on whichever threads claim them), and returns when all are done. How the range is cut depends on threads(): callers
  // must not make results depend on it (the kernels write disjoint outputs, and reductions sum
  // fixed rows). An exception from fn is rethrown here (the first one).
  template <class F>
  void parallelFor(int n, F&& fn) {
    if (n <= 0) return;
    using Fn = std::remove_reference_t<F>;
    auto call = [](void* ctx, int begin, int end) { (*static_cast<Fn*>(ctx))(begin, end); };
    run(n, call, const_cast<void*>(static_cast<const void*>(&fn)));
  }

 static constexpr int kChunksPerThread = 4;

 private:
  using Call = void (*)(void*, int, int);
  // The job word: the dispatch's generation (bits 24..63), its chunk count (12..23) and the next
  // unclaimed chunk (0..11), changed together so that a claim is one compare-and-swap and a
  // thread that still looks at the previous dispatch can never claim a chunk of the next.
  static constexpr int kChunkBits = 12;
  static constexpr int kMaxChunks = (1 << kChunkBits) - 1;
  void run(int n, Call call, void* ctx);
  void work(int index);
  void claimAndRun(std::uint64_t generation);
  void runChunk(int chunk, int chunks);

  int threads_;
  std::vector<std::thread> workers_;
  // The job in flight (written by the calling thread before it publishes job_; read by a thread
  // only after it has claimed one of the job's chunks, so they do not change while it runs).
  Call call_ = nullptr;
  void* ctx_ = nullptr;
  int n_ = 0;
  std::uint64_t generation_ = 0;  // the calling thread's count of dispatches
  std::atomic<std::uint64_t> job_{0};
  std::atomic<int> done_chunks_{0};
  std::atomic<bool> failed_{false};
  std::exception_ptr error_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  std::atomic<bool> stopping_{false};
};

}  // namespace hf::cpu
