// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// PeriodicClock: wakes a thread every period on absolute deadlines (clock_nanosleep with
// TIMER_ABSTIME on CLOCK_MONOTONIC), so the rate does not drift with the work done per period.
// A wake-up later than a whole period skips the missed deadlines (counted) instead of running
// a burst of catch-up periods.
#include <cstdint>
#include <string>

namespace hf::haptics {

class PeriodicClock {
 public:
  explicit PeriodicClock(double period_s);
  void start();        // the first deadline is one period from now
  double waitNext();   // sleeps until the next deadline; returns the wake-up time (s)
  double periodS() const { return period_s_; }
  std::uint64_t skipped() const { return skipped_; }

 private:
  double period_s_;
  std::int64_t period_ns_;
  std::int64_t next_ns_ = 0;
  std::uint64_t skipped_ = 0;
};

// Asks for SCHED_FIFO at `priority` for the calling thread. Returns "" on success, else a
// sentence saying why not and what that means (the thread keeps its normal priority).
std::string requestRealtimePriority(int priority);

}  // namespace hf::haptics
