// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// TraceRing<T>: a single-producer single-consumer queue of fixed capacity (the haptic thread
// pushes one record per period, the host drains them). push() never blocks: when the ring is
// full the record is dropped and counted.
#include <atomic>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace hf::haptics {

template <class T>
class TraceRing {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  explicit TraceRing(std::size_t capacity) : buf_(capacity) {}
  std::size_t capacity() const { return buf_.size(); }

  bool push(const T& v) {  // producer only
    if (buf_.empty()) return false;
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= buf_.size()) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    buf_[head % buf_.size()] = v;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  std::size_t drain(std::vector<T>& out) {  // consumer only; appends, returns how many
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    for (std::uint64_t i = tail; i < head; ++i) out.push_back(buf_[i % buf_.size()]);
    tail_.store(head, std::memory_order_release);
    return static_cast<std::size_t>(head - tail);
  }

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::vector<T> buf_;
  std::atomic<std::uint64_t> head_{0}, tail_{0}, dropped_{0};
};

}  // namespace hf::haptics
