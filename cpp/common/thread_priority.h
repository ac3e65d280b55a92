// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Threads' CPU priority (Linux niceness) and names, so that background work (a simulation beside
// Blender's drawing on a CPU GL device) yields the cores to an interactive thread when both want
// them. On Linux niceness and the name belong to each thread and are copied to the threads it
// starts. Raising niceness needs no privilege; lowering it below the start does (CAP_SYS_NICE).
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#if defined(__linux__)
#include <dirent.h>
#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <fstream>
#endif

namespace hf {

// How much nicer a thread may be made: 0 (unchanged) to 19 (the lowest priority).
inline constexpr int kMaxNicenessIncrement = 19;

#if defined(__linux__)
inline int currentThreadId() { return static_cast<int>(::syscall(SYS_gettid)); }

// The niceness of thread `tid` of this process (-20..19), or 0 when it cannot be read.
inline int threadNiceness(int tid) {
  errno = 0;
  const int n = ::getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
  return (n == -1 && errno != 0) ? 0 : n;
}

// Sets thread `tid`'s niceness (PRIO_PROCESS with a thread id addresses one thread on Linux).
// Returns "" on success, else why not.
inline std::string setThreadNiceness(int tid, int niceness) {
  if (::setpriority(PRIO_PROCESS, static_cast<id_t>(tid), niceness) != 0) {
    return "setpriority(" + std::to_string(niceness) + ") failed: " + std::strerror(errno);
  }
  return "";
}

// The ids of this process's threads now (/proc/self/task).
inline std::vector<int> threadIds() {
  std::vector<int> ids;
  if (DIR* dir = ::opendir("/proc/self/task")) {
    while (const dirent* e = ::readdir(dir)) {
      if (e->d_name[0] >= '0' && e->d_name[0] <= '9') ids.push_back(std::atoi(e->d_name));
    }
    ::closedir(dir);
  }
  return ids;
}

// Thread `tid`'s name ("" when it has ended).
inline std::string threadName(int tid) {
  std::ifstream f("/proc/self/task/" + std::to_string(tid) + "/comm");
  std::string name;
  std::getline(f, name);
  return name;
}

// Names the calling thread (at most 15 characters are kept); threads it starts inherit the name
// until they set their own.
inline void nameCurrentThread(const char* name) { ::pthread_setname_np(::pthread_self(), name); }
#endif

// Adds `increment` (0..kMaxNicenessIncrement) to the calling thread's niceness, capped at 19.
// Returns "" on success (or for 0), else why not.
inline std::string lowerCurrentThreadPriority(int increment) {
  if (increment <= 0) return "";
#if defined(__linux__)
  const int tid = currentThreadId();
  return setThreadNiceness(tid, std::min(19, threadNiceness(tid) + increment));  // 19: the lowest priority
#else
  return "thread niceness is only supported on Linux";
#endif
}

}  // namespace hf
