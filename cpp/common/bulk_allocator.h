// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Host arrays a whole field long that are written once, right after they are made: a
// checkpoint's read-back (Simulation::saveState), handed on to Python as numpy arrays and freed
// there a frame or two later (the bake's writer thread).
//
// With std::vector<float> such an array cost more to make than to fill: a fresh 2.8 MB array (one
// field of the seed grid) faulted in 700 pages of 4 KiB, each zeroed by the kernel, and resize()
// wrote zeros over it again. Reading a 100 x 100 x 70 state back (six fields, 17 MB) took 10 ms,
// of which the copy was about 2 (perf: page faults and clear_page about 60 %). BulkAllocator
// leaves the elements uninitialized on resize (the caller writes every one) and keeps the blocks
// of freed arrays (up to kBulkPoolBytes in all) for the next arrays of the same size, so a
// steady stream of read-backs touches memory that is already mapped. (Asking for transparent huge
// pages instead cut the typical read-back as far but stalled one in a few for 50-90 ms on this
// VM: not kept.)
#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

namespace hf {

inline constexpr std::size_t kBulkMinBytes = std::size_t{1} << 20;   // smaller arrays: the heap's
inline constexpr std::size_t kBulkPoolBytes = std::size_t{64} << 20;  // freed blocks kept at most

namespace detail {

// The freed blocks of BulkAllocator, by size (page multiples), shared by every thread. Never
// destroyed: an array Python frees while the process exits still finds it.
class BulkPool {
 public:
  static BulkPool& instance() {
    static BulkPool* pool = new BulkPool;  // NOLINT(cppcoreguidelines-owning-memory): lives to exit
    return *pool;
  }
  // A kept block of exactly `bytes`, or nullptr.
  void* take(std::size_t bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (std::size_t i = count_; i-- > 0;) {
      if (blocks_[i].bytes == bytes) {
        void* p = blocks_[i].data;
        remove(i);
        return p;
      }
    }
    return nullptr;
  }
  // Keeps `data` when it fits under the cap, unmapping the oldest blocks to make room; unmaps it
  // otherwise. Allocates nothing (it runs inside a deallocation).
  void give(void* data, std::size_t bytes) noexcept {
    if (bytes > kBulkPoolBytes) {
      munmap(data, bytes);
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    while (count_ > 0 && (held_ + bytes > kBulkPoolBytes || count_ == kMaxBlocks)) {
      munmap(blocks_[0].data, blocks_[0].bytes);
      remove(0);
    }
    blocks_[count_++] = {data, bytes};
    held_ += bytes;
  }
  std::size_t heldBytes() {
    std::lock_guard<std::mutex> lock(mutex_);
    return held_;
  }

 private:
  struct Block {
    void* data;
    std::size_t bytes;
  };
  static constexpr std::size_t kMaxBlocks = 32;
  BulkPool() = default;
  void remove(std::size_t i) {
    held_ -= blocks_[i].bytes;
    for (std::size_t j = i + 1; j < count_; ++j) blocks_[j - 1] = blocks_[j];
    --count_;
  }
  std::mutex mutex_;
  Block blocks_[kMaxBlocks] = {};  // oldest first
  std::size_t count_ = 0;
  std::size_t held_ = 0;
};

inline std::size_t bulkMappedBytes(std::size_t bytes) {
  constexpr std::size_t kPage = 4096;
  return (bytes + kPage - 1) & ~(kPage - 1);
}

}  // namespace detail

template <class T>
class BulkAllocator {
 public:
  using value_type = T;

  BulkAllocator() noexcept = default;
  template <class U>
  BulkAllocator(const BulkAllocator<U>&) noexcept {}  // NOLINT(google-explicit-constructor): rebinding

  T* allocate(std::size_t n) {
    if (n > (SIZE_MAX - 4096) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kBulkMinBytes) return std::allocator<T>{}.allocate(n);
    const std::size_t mapped = detail::bulkMappedBytes(bytes);
    if (void* kept = detail::BulkPool::instance().take(mapped)) return static_cast<T*>(kept);
    void* p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    return static_cast<T*>(p);
  }

  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kBulkMinBytes) {
      std::allocator<T>{}.deallocate(p, n);
    } else {
      detail::BulkPool::instance().give(p, detail::bulkMappedBytes(bytes));
    }
  }

  // Default-initialization: resize(n) leaves a float's value unset instead of writing 0.
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) {
      ::new (static_cast<void*>(p)) U;
    } else {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
  }

  template <class U>
  bool operator==(const BulkAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const BulkAllocator<U>&) const noexcept {
    return false;
  }
};

// A field's worth of floats whose every element the owner writes before reading (see above).
using BulkFloats = std::vector<float, BulkAllocator<float>>;

}  // namespace hf
