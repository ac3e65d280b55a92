// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/thread_pool.h"

#include "cpu/float_mode.h"

#include <chrono>
#include <exception>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define HF_PAUSE() _mm_pause()
#else
#define HF_PAUSE() std::this_thread::yield()
#endif

namespace hf::cpu {
namespace {

// How long a thread spins before it sleeps: a worker for the next dispatch, the calling thread for
// the other threads' last chunks. Timed, not counted: a PAUSE takes 11 ns on one x86 core and
// 40 on another, and the 4000 of before were 45 us on the Intel VM, shorter than most gaps
// between a solve's parallel dispatches (its coarse levels run on the calling thread), so the
// worker slept 15-25 times a seed-grid step and each wake-up (a futex in a VM) cost the
// dispatch after it about 0.15 ms. 1 ms covers the gaps inside a step and still lets the workers
// sleep between steps (the live session idles between its steps; at 32^3 no dispatch is parallel).
constexpr std::chrono::microseconds kSpinTime{1000};
constexpr int kPausesPerClockRead = 16;

// Spins until done() (true) or kSpinTime has passed (false).
template <class Done>
bool spinUntil(Done done) {
  const auto give_up = std::chrono::steady_clock::now() + kSpinTime;
  for (int spin = 1;; ++spin) {
    if (done()) return true;
    if (spin % kPausesPerClockRead == 0 && std::chrono::steady_clock::now() >= give_up) return false;
    HF_PAUSE();
  }
}

constexpr std::uint64_t kFieldMask = (std::uint64_t{1} << 12) - 1;
std::uint64_t generationOf(std::uint64_t job) { return job >> 24; }
int chunksOf(std::uint64_t job) { return static_cast<int>((job >> 12) & kFieldMask); }
int nextOf(std::uint64_t job) { return static_cast<int>(job & kFieldMask); }

}  // namespace

ThreadPool::ThreadPool(int threads) : threads_(threads < 1 ? 1 : threads) {
  for (int i = 1; i < threads_; ++i) workers_.emplace_back([this, i] { work(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_.store(true);
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::runChunk(int chunk, int chunks) {
  const int begin = static_cast<int>(static_cast<long long>(n_) * chunk / chunks);
  const int end = static_cast<int>(static_cast<long long>(n_) * (chunk + 1) / chunks);
  try {
    call_(ctx_, begin, end);
  } catch (...) {
    if (!failed_.exchange(true)) error_ = std::current_exception();
  }
  if (done_chunks_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks) {
    std::lock_guard<std::mutex> lock(mutex_);  // the caller may be asleep on done_
    done_.notify_all();
  }
}

void ThreadPool::claimAndRun(std::uint64_t generation) {
  std::uint64_t job = job_.load(std::memory_order_acquire);
  while (generationOf(job) == generation && nextOf(job) < chunksOf(job)) {
    if (job_.compare_exchange_weak(job, job + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      runChunk(nextOf(job), chunksOf(job));
      job = job_.load(std::memory_order_acquire);
    }
  }
}

void ThreadPool::run(int n, Call call, void* ctx) {
  int chunks = threads_ * kChunksPerThread;
  if (chunks > kMaxChunks) chunks = kMaxChunks;
  if (chunks > n) chunks = n;
  if (threads_ == 1 || chunks == 1) {
    call(ctx, 0, n);
    return;
  }
  call_ = call;
  ctx_ = ctx;
  n_ = n;
  failed_.store(false);
  error_ = nullptr;
  done_chunks_.store(0, std::memory_order_relaxed);
  ++generation_;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_.store((generation_ << 24) | (static_cast<std::uint64_t>(chunks) << 12), std::memory_order_release);
  }
  wake_.notify_all();
  claimAndRun(generation_);
  auto all_done = [&] { return done_chunks_.load(std::memory_order_acquire) == chunks; };
  if (!spinUntil(all_done)) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, all_done);
  }
  if (failed_.load()) std::rethrow_exception(error_);
}

void ThreadPool::work(int) {
  flushDenormalsOnThisThread();  // as the dispatching thread runs its chunks (cpu/float_mode.h)
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t now = seen;
    spinUntil([&] {
      now = generationOf(job_.load(std::memory_order_acquire));
      return now != seen || stopping_.load(std::memory_order_relaxed);
    });
    if (now == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] {
        return stopping_.load() || generationOf(job_.load(std::memory_order_acquire)) != seen;
      });
      now = generationOf(job_.load(std::memory_order_acquire));
    }
    if (stopping_.load()) return;
    seen = now;
    claimAndRun(seen);
  }
}

}  // namespace hf::cpu
