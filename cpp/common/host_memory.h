// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The host's available memory (/proc/meminfo MemAvailable), what a device that keeps its fields
// in host memory (llvmpipe, the CPU backend) may count on.
#include <fstream>
#include <string>

namespace hf {

// MemAvailable in KiB; 0 if unreadable.
inline long long hostAvailableKb() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  long long kb = 0;
  while (in >> key >> kb) {
    if (key == "MemAvailable:") return kb;
    in.ignore(256, '\n');
  }
  return 0;
}

}  // namespace hf
