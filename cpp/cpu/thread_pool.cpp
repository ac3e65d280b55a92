// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/thread_pool.h"

#include <exception>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define HF_PAUSE() _mm_pause()
#else
#define HF_PAUSE() std::this_thread::yield()
#endif

namespace hf::cpu {
namespace {

// Polls before sleeping: about 20-50 us, longer than the gap between two dispatches of a step,
// far shorter than the gap between steps.
constexpr int kSpins = 4000;

}  // namespace

ThreadPool::ThreadPool(int threads) : threads_(threads < 1 ? 1 : threads) {
  for (int i = 1; i < threads_; ++i) workers_.emplace_back([this, i] { work(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    generation_.fetch_add(1);
  }
  wake_.notify_all();
  for (auto& t : workers_) t.join();
}

void ThreadPool::runChunk(int chunk) {
  if (chunk >= chunks_) return;
  const int begin = static_cast<int>(static_cast<long long>(n_) * chunk / chunks_);
  const int end = static_cast<int>(static_cast<long long>(n_) * (chunk + 1) / chunks_);
  try {
    call_(ctx_, begin, end);
  } catch (...) {
    if (!failed_.exchange(true)) error_ = std::current_exception();
  }
}

void ThreadPool::run(int n, Call call, void* ctx) {
  const int chunks = n < threads_ ? n : threads_;
  if (chunks == 1) {
    call(ctx, 0, n);
    return;
  }
  call_ = call;
  ctx_ = ctx;
  n_ = n;
  chunks_ = chunks;
  failed_.store(false);
  error_ = nullptr;
  pending_.store(threads_ - 1, std::memory_order_relaxed);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  runChunk(0);
  for (int spin = 0; pending_.load(std::memory_order_acquire) != 0; ++spin) {
    if (spin < kSpins) {
      HF_PAUSE();
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
  }
  if (failed_.load()) std::rethrow_exception(error_);
}

void ThreadPool::work(int index) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t now = generation_.load(std::memory_order_acquire);
    for (int spin = 0; now == seen && spin < kSpins; ++spin) {
      HF_PAUSE();
      now = generation_.load(std::memory_order_acquire);
    }
    if (now == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
      now = generation_.load(std::memory_order_acquire);
    }
    seen = now;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_) return;
    }
    runChunk(index);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      done_.notify_all();
    }
  }
}

}  // namespace hf::cpu
