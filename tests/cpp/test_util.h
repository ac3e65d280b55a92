#pragma once
// Helpers shared by the GoogleTest files (not a test itself: the CMake glob takes only *.cpp).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "gl/gl_worker.h"

namespace hf::test {

// Fixture for tests of GL-level classes: one GL worker (thread + context) per test suite.
// Every GL object must be created, used and destroyed inside onGl(...).
class GlTest : public ::testing::Test {
 public:
  static void SetUpTestSuite() { worker_ = std::make_unique<gl::GlWorker>(); }
  static void TearDownTestSuite() { worker_.reset(); }
  void SetUp() override { ASSERT_NE(worker_, nullptr) << "no GL context could be made"; }

  // Runs fn on the suite's GL thread (free helpers of a test file may call it too).
  static gl::GlWorker& worker() { return *worker_; }
  template <class F>
  static auto onGl(F&& fn) {
    return worker_->call(std::forward<F>(fn));
  }

 private:
  static inline std::unique_ptr<gl::GlWorker> worker_;
};

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
