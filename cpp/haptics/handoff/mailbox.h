// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Mailbox<T>: the latest value of T, handed between threads without locks (a sequence lock).
// Writers (any number) take turns through one compare-and-swap on the sequence counter, so a
// write never waits on a reader; readers never write shared memory and never block: tryRead()
// gives up after a few torn attempts (a writer was mid-copy) and the caller keeps the value it
// had. The haptic thread only ever calls tryRead() or is the only writer of its own mailbox.
// The payload lives in atomic words, so concurrent access is well defined in C++.
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace hf::haptics {

template <class T>
class Mailbox {
  static_assert(std::is_trivially_copyable_v<T>, "Mailbox payloads are copied word by word");
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

 public:
  static constexpr int kReadAttempts = 64;

  // Publishes v; returns its version (1 for the first write, then 2, 3, ...).
  std::uint64_t write(const T& v) {
    std::uint64_t s = seq_.load(std::memory_order_relaxed);
    for (;;) {
      if ((s & 1u) == 0 && seq_.compare_exchange_weak(s, s + 1, std::memory_order_acquire, std::memory_order_relaxed)) {
        break;
      }
      if (s & 1u) s = seq_.load(std::memory_order_relaxed);  // another writer is mid-copy
    }
    std::uint64_t buf[kWords] = {};
    std::memcpy(buf, &v, sizeof(T));
    // Release stores: a reader whose (acquire) load sees one of these words also sees the odd
    // sequence above, so its second sequence check fails. (Plain moves on x86; no fences, which
    // ThreadSanitizer cannot follow.)
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(buf[i], std::memory_order_release);
    seq_.store(s + 2, std::memory_order_release);
    return (s + 2) / 2;
  }

  // Copies the latest value into out and returns true; false (out untouched) if nothing was
  // written yet or every attempt overlapped a write. version (optional) gets its version.
  bool tryRead(T& out, std::uint64_t* version = nullptr) const {
    for (int attempt = 0; attempt < kReadAttempts; ++attempt) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 == 0) return false;
      if (s0 & 1u) continue;
      std::uint64_t buf[kWords];
      for (std::size_t i = 0; i < kWords; ++i) buf[i] = words_[i].load(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) {
        // The bytes go into a T of its own, which is then assigned: `out` may be a subobject of a
        // larger object (a base, whose tail padding may hold a derived member, or a member such as
        // LoopStats::passivity), and a byte copy of sizeof(T) is defined only into an object that
        // is not a potentially-overlapping subobject. GCC 12 sized a member destination as its
        // first field ("writing 64 bytes into a region of size 8" in HapticLoop::stats()).
        T value;
        std::memcpy(&value, buf, sizeof(T));
        out = value;
        if (version) *version = s0 / 2;
        return true;
      }
    }
    return false;
  }

  // Version of the latest complete write (0: none yet).
  std::uint64_t version() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> seq_{0};
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace hf::haptics
