// SPDX-License-Identifier: GPL-3.0-or-later
// The CPU backend's thread pool (cpu/thread_pool.h): every index of a dispatch runs exactly once,
// in contiguous chunks, whichever threads claim them; an exception reaches the caller after the
// other chunks are done; and back-to-back dispatches (a step's hundreds) never mix, also when a
// worker is kept off its core for a while; and workers that have nothing to do go to sleep.
#include <gtest/gtest.h>

#include <time.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include "cpu/thread_pool.h"

namespace hf::cpu {
namespace {

TEST(CpuThreadPool, EveryIndexRunsOnceInContiguousChunks) {
  for (int threads : {1, 2, 3, 4}) {
    ThreadPool pool(threads);
    for (int n : {1, 2, 3, 7, 8, 9, 100, 4099}) {
      std::vector<std::atomic<int>> hits(static_cast<std::size_t>(n));
      std::atomic<int> chunks{0};
      pool.parallelFor(n, [&](int begin, int end) {
        ASSERT_LT(begin, end);
        chunks.fetch_add(1);
        for (int i = begin; i < end; ++i) hits[static_cast<std::size_t>(i)].fetch_add(1);
      });
      for (int i = 0; i < n; ++i) ASSERT_EQ(hits[static_cast<std::size_t>(i)].load(), 1) << threads << " " << n << " " << i;
      EXPECT_LE(chunks.load(), threads * ThreadPool::kChunksPerThread);
      EXPECT_LE(chunks.load(), n);
    }
  }
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Workers spin a short while for the next dispatch, then sleep: an idle pool costs no CPU. (A
// worker that never slept would use the whole 400 ms; 100 ms leaves room for a loaded machine.)
TEST(CpuThreadPool, AnIdlePoolSleeps) {
  ThreadPool pool(4);
  std::atomic<int> sum{0};
  pool.parallelFor(64, [&](int begin, int end) { sum.fetch_add(end - begin); });
  ASSERT_EQ(sum.load(), 64);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // past every worker's spin
  const double before = processCpuSeconds();
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  EXPECT_LT(processCpuSeconds() - before, 0.1);
}

TEST(CpuThreadPool, ManyDispatchesInARowStaySeparate) {
  ThreadPool pool(4);
  std::vector<int> data(1000, 0);
  for (int round = 1; round <= 2000; ++round) {
    pool.parallelFor(static_cast<int>(data.size()), [&](int begin, int end) {
      for (int i = begin; i < end; ++i) {
        ASSERT_EQ(data[static_cast<std::size_t>(i)], round - 1);  // the previous dispatch is wholly done
        data[static_cast<std::size_t>(i)] = round;
      }
    });
  }
  for (int v : data) ASSERT_EQ(v, 2000);
}

TEST(CpuThreadPool, ASlowChunkDoesNotLoseTheOthers) {
  ThreadPool pool(2);
  std::vector<std::atomic<int>> hits(64);
  pool.parallelFor(64, [&](int begin, int end) {
    if (begin == 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // its thread is held up
    for (int i = begin; i < end; ++i) hits[static_cast<std::size_t>(i)].fetch_add(1);
  });
  for (auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(CpuThreadPool, AnExceptionReachesTheCallerAndThePoolGoesOn) {
  ThreadPool pool(3);
  std::atomic<int> ran{0};
  EXPECT_THROW(pool.parallelFor(300,
                                [&](int begin, int end) {
                                  ran.fetch_add(end - begin);
                                  if (begin == 0) throw std::runtime_error("chunk failed");
                                }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 300);  // every chunk ran before the caller saw the error
  std::atomic<int> total{0};
  pool.parallelFor(300, [&](int begin, int end) { total.fetch_add(end - begin); });
  EXPECT_EQ(total.load(), 300);
}

}  // namespace
}  // namespace hf::cpu
