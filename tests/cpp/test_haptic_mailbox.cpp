// SPDX-License-Identifier: GPL-3.0-or-later
// The lock-free hand-offs between threads: Mailbox (seqlock), TraceRing (SPSC), SampleWindow.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "haptics/handoff/mailbox.h"
#include "haptics/loop/sample_window.h"
#include "haptics/loop/trace_ring.h"

namespace hf::haptics {
namespace {

// Every word holds the same value, so a torn copy (half of one write, half of another) shows.
struct Payload {
  std::array<std::uint64_t, 9> words;
};

TEST(HapticMailbox, ConcurrentWritersAndReadersNeverSeeATornValue) {
  Mailbox<Payload> box;
  Payload probe{};
  EXPECT_FALSE(box.tryRead(probe));  // nothing written yet
  EXPECT_EQ(box.version(), 0u);
  constexpr int kWriters = 2, kReaders = 2;
  constexpr std::uint64_t kMinWrites = 50000, kMinReads = 20000;
  std::atomic<int> readers_ready{0}, writers_left{kWriters};
  std::atomic<std::uint64_t> torn{0}, reads{0}, backwards{0};
  std::array<std::uint64_t, kWriters> written{};
  std::vector<std::thread> threads;
  for (int w = 0; w < kWriters; ++w) {
    threads.emplace_back([&, w] {
      while (readers_ready.load() < kReaders) std::this_thread::yield();
      Payload p{};
      std::uint64_t i = 0;
      // Keep writing until the readers have overlapped plenty of writes (a loaded machine may
      // not schedule them for a while).
      while (i < kMinWrites || reads.load(std::memory_order_relaxed) < kMinReads) {
        ++i;
        p.words.fill((static_cast<std::uint64_t>(w) << 32) | i);
        box.write(p);
      }
      written[w] = i;
      writers_left.fetch_sub(1);
    });
  }
  for (int r = 0; r < kReaders; ++r) {
    threads.emplace_back([&] {
      std::array<std::uint64_t, kWriters> last{};  // per writer, the counters seen must not go back
      std::uint64_t last_version = 0;
      Payload p{};
      readers_ready.fetch_add(1);
      while (writers_left.load() > 0) {
        std::uint64_t version = 0;
        if (!box.tryRead(p, &version)) continue;
        reads.fetch_add(1, std::memory_order_relaxed);
        for (auto v : p.words) {
          if (v != p.words[0]) {
            torn.fetch_add(1);
            break;
          }
        }
        const std::uint64_t writer = p.words[0] >> 32, count = p.words[0] & 0xffffffffu;
        if (writer >= kWriters || count < last[writer] || version < last_version) backwards.fetch_add(1);
        if (writer < kWriters) last[writer] = count;
        last_version = version;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(torn.load(), 0u);
  EXPECT_EQ(backwards.load(), 0u);
  EXPECT_GE(reads.load(), kMinReads);
  EXPECT_EQ(box.version(), written[0] + written[1]);  // no write lost its turn
  ASSERT_TRUE(box.tryRead(probe));
  const std::uint64_t last_writer = probe.words[0] >> 32;
  ASSERT_LT(last_writer, static_cast<std::uint64_t>(kWriters));
  EXPECT_EQ(probe.words[0] & 0xffffffffu, written[last_writer]);  // that writer's last write
}

TEST(HapticTraceRing, DeliversInOrderAndCountsDrops) {
  TraceRing<std::uint64_t> ring(1024);
  constexpr std::uint64_t kItems = 200000;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems; ++i) ring.push(i);
    done = true;
  });
  std::vector<std::uint64_t> got;
  while (!done.load()) ring.drain(got);
  producer.join();
  ring.drain(got);
  for (std::size_t i = 1; i < got.size(); ++i) ASSERT_LT(got[i - 1], got[i]);
  EXPECT_EQ(got.size() + ring.dropped(), kItems);
  EXPECT_GE(got.size(), ring.capacity());  // at least one full ring reached the consumer
  TraceRing<int> none(0);
  EXPECT_FALSE(none.push(1));
}

TEST(HapticSampleWindow, PercentilesOfKnownSamples) {
  SampleWindow<100> w;
  for (int i = 1; i <= 250; ++i) w.add(static_cast<float>(i));  // keeps the latest 100: 151..250
  const Percentiles p = summarize(w.values());
  EXPECT_EQ(p.count, 100u);
  EXPECT_EQ(p.max, 250.0);
  EXPECT_NEAR(p.p50, 200.0, 1.0);
  EXPECT_NEAR(p.p99, 249.0, 1.0);
  EXPECT_NEAR(p.mean, 200.5, 1e-9);
  EXPECT_EQ(summarize({}).count, 0u);
}

}  // namespace
}  // namespace hf::haptics
