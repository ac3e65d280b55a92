// SPDX-License-Identifier: GPL-3.0-or-later
// The engine's log queue (common/log_sink.h) as the haptic and simulation threads use it: bounded,
// drops counted, never lost or duplicated under concurrent emitters, drained oldest first.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <thread>
#include <vector>

#include "common/log_sink.h"

namespace hf::log {
namespace {

TEST(EngineLogSink, KeepsOrderBoundsTheQueueAndCountsDrops) {
  LogSink sink;
  std::uint64_t dropped = 99;
  EXPECT_TRUE(sink.drain(&dropped).empty());
  EXPECT_EQ(dropped, 0u);
  for (std::size_t i = 0; i < kLogCapacity + 10; ++i) {
    sink.emit(i % 2 ? Level::Warning : Level::Info, "hapticfluid.haptics", "message " + std::to_string(i));
  }
  const std::vector<Message> got = sink.drain(&dropped);
  ASSERT_EQ(got.size(), kLogCapacity);
  EXPECT_EQ(dropped, 10u);  // the newest ten did not fit
  EXPECT_EQ(got.front().text, "message 0");
  EXPECT_EQ(got.front().level, Level::Info);
  EXPECT_EQ(got[1].level, Level::Warning);
  EXPECT_EQ(got.back().text, "message " + std::to_string(kLogCapacity - 1));
  EXPECT_EQ(got.back().logger, "hapticfluid.haptics");
  EXPECT_TRUE(sink.drain(&dropped).empty());  // drained once, and the count starts again
  EXPECT_EQ(dropped, 0u);
  EXPECT_EQ(static_cast<int>(Level::Warning), 30);  // Python logging's WARNING
}

TEST(EngineLogSink, ConcurrentEmittersAndADrainerLoseNothingThatFits) {
  LogSink sink;
  constexpr int kThreads = 4, kEach = 1000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&sink, t] {
      for (int i = 0; i < kEach; ++i) sink.emit(Level::Warning, "hapticfluid.session", std::to_string(t * kEach + i));
    });
  }
  std::set<std::string> seen;
  std::uint64_t dropped_total = 0;
  std::size_t received = 0;
  auto take = [&] {
    std::uint64_t dropped = 0;
    for (const Message& m : sink.drain(&dropped)) {
      seen.insert(m.text);
      ++received;
    }
    dropped_total += dropped;
  };
  for (int i = 0; i < 200; ++i) take();
  for (auto& th : threads) th.join();
  take();
  EXPECT_EQ(received, seen.size());                           // nothing delivered twice
  EXPECT_EQ(received + dropped_total, std::size_t{kThreads * kEach});  // every message delivered or counted
}

}  // namespace
}  // namespace hf::log
