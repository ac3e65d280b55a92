// SPDX-License-Identifier: GPL-3.0-or-later
#include "haptics/loop/periodic_clock.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cerrno>
#include <cstring>

namespace hf::haptics {

namespace {
std::int64_t nowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}
}  // namespace

PeriodicClock::PeriodicClock(double period_s)
    : period_s_(period_s), period_ns_(static_cast<std::int64_t>(period_s * 1e9 + 0.5)) {}

void PeriodicClock::start() { next_ns_ = nowNs() + period_ns_; }

double PeriodicClock::waitNext() {
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(next_ns_ / 1000000000LL);
  deadline.tv_nsec = static_cast<long>(next_ns_ % 1000000000LL);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
  const std::int64_t now = nowNs();
  next_ns_ += period_ns_;
  if (now > next_ns_) {  // woke more than a period late: skip to the next deadline ahead
    const std::int64_t missed = (now - next_ns_) / period_ns_ + 1;
    skipped_ += static_cast<std::uint64_t>(missed);
    next_ns_ += missed * period_ns_;
  }
  return 1e-9 * static_cast<double>(now);
}

std::string requestRealtimePriority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) return "";
  return std::string("real-time priority (SCHED_FIFO ") + std::to_string(priority) + ") not granted: " +
         std::strerror(rc) +
         "; the haptic loop runs at normal priority and its period may jitter under load "
         "(grant it with `ulimit -r` / rtprio in /etc/security/limits.conf, or CAP_SYS_NICE)";
}

}  // namespace hf::haptics
