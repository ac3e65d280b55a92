// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Helpers shared by the GoogleTest files of every layer, GL or not (test_util.h adds the GL
// fixture; the haptics tests, which link no GL, include only this).
#include <chrono>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>

namespace hf::test {

// Sets an environment variable for the lifetime of the guard, then restores the old value.
class EnvGuard {
 public:
  EnvGuard(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value != nullptr) ::setenv(name, value, 1); else ::unsetenv(name);
  }
  ~EnvGuard() {
    if (old_) ::setenv(name_.c_str(), old_->c_str(), 1); else ::unsetenv(name_.c_str());
  }
  EnvGuard(const EnvGuard&) = delete;
  EnvGuard& operator=(const EnvGuard&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

// Polls pred every 2 ms until it holds or `limit` has passed; returns its last value.
template <class Pred>
bool waitFor(Pred pred, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return pred();
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace hf::test
