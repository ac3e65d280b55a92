// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// SampleWindow: the latest N samples of a measurement (periods, latencies), written by one
// thread without locks and copied out by another for percentiles. Slots are relaxed atomics:
// a copy taken during writes may mix two neighbouring windows, which statistics tolerate.
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace hf::haptics {

struct Percentiles {
  std::uint64_t count = 0;  // samples in the window
  double p50 = 0.0, p99 = 0.0, max = 0.0, mean = 0.0;
};

// p50/p99/max/mean of a set of samples (nearest rank); all zero for none.
inline Percentiles summarize(std::vector<float> v) {
  Percentiles p;
  const std::size_t n = v.size();
  p.count = n;
  if (n == 0) return p;
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {
    return static_cast<double>(v[std::min<std::size_t>(n - 1, static_cast<std::size_t>(q * (n - 1) + 0.5))]);
  };
  p.p50 = at(0.50);
  p.p99 = at(0.99);
  p.max = v.back();
  double sum = 0.0;
  for (float x : v) sum += x;
  p.mean = sum / static_cast<double>(n);
  return p;
}

template <std::size_t N>
class SampleWindow {
 public:
  void add(float v) {
    const std::uint64_t i = written_.load(std::memory_order_relaxed);
    slots_[i % N].store(v, std::memory_order_relaxed);
    written_.store(i + 1, std::memory_order_release);
  }
  std::uint64_t written() const { return written_.load(std::memory_order_acquire); }
  void clear() { written_.store(0, std::memory_order_release); }

  std::vector<float> values() const {  // the window's samples, oldest slot order not kept
    const std::uint64_t n = std::min<std::uint64_t>(written(), N);
    std::vector<float> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = slots_[i].load(std::memory_order_relaxed);
    return v;
  }

 private:
  std::array<std::atomic<float>, N> slots_{};
  std::atomic<std::uint64_t> written_{0};
};

}  // namespace hf::haptics
