// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The engine's messages for Python's `logging`: warnings raised on any engine thread (the 1 kHz
// haptic thread, the simulation thread that owns the GL context, the host) are queued here and
// delivered later by the Python module, on the host's thread, under the GIL (see
// cpp/python/bind_log.cpp: hapticfluid._core.flush_log(), also called by the bindings after the
// calls that may have queued something).
//
// emit() never takes the GIL and never blocks on anything but a short mutex held only to move one
// message into the queue (the drainer holds it only to swap the queue out). The queue is bounded
// (kLogCapacity messages): a message that does not fit is dropped and counted, and the count is
// reported with the next flush. emit() never throws (an allocation failure counts as a drop).
//
// Loggers are named per engine layer: "hapticfluid.gl", "hapticfluid.fluid",
// "hapticfluid.haptics", "hapticfluid.session". Levels are Python logging's numbers.
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace hf::log {

enum class Level : int { Debug = 10, Info = 20, Warning = 30, Error = 40 };

inline constexpr std::size_t kLogCapacity = 256;  // messages queued at most between two flushes

struct Message {
  std::string logger;  // e.g. "hapticfluid.haptics"
  Level level = Level::Warning;
  std::string text;
};

class LogSink {
 public:
  void emit(Level level, const char* logger, std::string text) noexcept {
    try {
      Message m{logger, level, std::move(text)};
      std::lock_guard<std::mutex> lock(mutex_);
      if (queue_.size() >= kLogCapacity) {
        ++dropped_;
        return;
      }
      queue_.push_back(std::move(m));
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++dropped_;
    }
  }
  // Everything queued so far, oldest first; *dropped: messages lost since the last drain.
  std::vector<Message> drain(std::uint64_t* dropped) {
    std::vector<Message> out;
    out.reserve(kLogCapacity);  // outside the lock: the swap below does not allocate
    std::lock_guard<std::mutex> lock(mutex_);
    out.swap(queue_);
    if (dropped) *dropped = dropped_;
    dropped_ = 0;
    return out;
  }

 private:
  std::mutex mutex_;
  std::vector<Message> queue_;
  std::uint64_t dropped_ = 0;
};

// The process's one sink (one per module: every layer is linked into hapticfluid._core).
inline LogSink& sink() {
  static LogSink s;
  return s;
}

inline void info(const char* logger, std::string text) noexcept { sink().emit(Level::Info, logger, std::move(text)); }
inline void warning(const char* logger, std::string text) noexcept {
  sink().emit(Level::Warning, logger, std::move(text));
}

}  // namespace hf::log
