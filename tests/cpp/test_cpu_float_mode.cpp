// SPDX-License-Identifier: GPL-3.0-or-later
// The CPU backend's float mode (cpu/float_mode.h): denormal results and operands are flushed to
// zero on the pool's workers and, for a dispatch, on the thread that dispatches, whose own mode
// comes back after it (Python's thread keeps IEEE denormals for numpy).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <limits>
#include <thread>
#include <vector>

#include "cpu/float_mode.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {
namespace {

// A product whose exact value is a denormal float: 1e-30 * 1e-10 (volatile: computed at run time).
float tinyProduct() {
  volatile float a = 1e-30f, b = 1e-10f;
  return a * b;
}

#if defined(__x86_64__) || defined(__i386__)
TEST(CpuFloatMode, ADispatchFlushesDenormalsAndGivesTheThreadItsModeBack) {
  std::thread([] {  // a new thread: the default mode, denormals kept
    EXPECT_GT(tinyProduct(), 0.0f);
    {
      FlushDenormals flush;
      EXPECT_EQ(tinyProduct(), 0.0f);
      volatile float denormal = std::numeric_limits<float>::denorm_min();
      EXPECT_EQ(denormal * 1.0f, 0.0f);  // a denormal operand is read as 0
    }
    EXPECT_GT(tinyProduct(), 0.0f);
    flushDenormalsOnThisThread();
    {
      FlushDenormals flush;  // the mode already set: left as it is, after too
    }
    EXPECT_EQ(tinyProduct(), 0.0f);
  }).join();
}

TEST(CpuFloatMode, ThePoolsWorkersFlushDenormals) {
  std::thread([] {
    ThreadPool pool(4);
    std::vector<float> products(64, -1.0f);
    std::atomic<int> on_workers{0};
    const std::thread::id caller = std::this_thread::get_id();
    {
      FlushDenormals flush;  // the dispatching thread, as CpuProgram::dispatch holds it
      pool.parallelFor(64, [&](int begin, int end) {
        if (std::this_thread::get_id() != caller) on_workers.fetch_add(1);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));  // so that the workers take chunks too
        for (int i = begin; i < end; ++i) products[static_cast<std::size_t>(i)] = tinyProduct();
      });
    }
    EXPECT_GT(on_workers.load(), 0);
    for (float p : products) EXPECT_EQ(p, 0.0f);
    EXPECT_GT(tinyProduct(), 0.0f);  // this thread's own mode came back
  }).join();
}
#endif

}  // namespace
}  // namespace hf::cpu
