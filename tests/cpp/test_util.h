// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The device fixture shared by the GoogleTest files of the device-level layers (not a test
// itself: the CMake globs take only *.cpp), and the device-free helpers of test_common.h.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <utility>

#include "compute/compute_worker.h"
#include "cpu/cpu_device.h"
#include "gl/gl_device.h"
#include "test_common.h"

namespace hf::test {

// The backend the device tests run on: HAPTICFLUID_BACKEND=cpu for the CPU device, else GL
// (ctest registers each of these binaries once per backend: tests/cpp/CMakeLists.txt).
inline bool testOnCpu() {
  const char* b = std::getenv("HAPTICFLUID_BACKEND");
  return b != nullptr && std::strcmp(b, "cpu") == 0;
}

inline std::unique_ptr<compute::ComputeWorker> makeTestWorker() {
  if (testOnCpu()) return std::make_unique<cpu::CpuWorker>();
  return std::make_unique<gl::GlWorker>();
}

// Fixture for tests of device-level classes: one worker (thread + device) per test suite.
// Every device object must be created, used and destroyed inside onGl(...).
class DeviceTest : public ::testing::Test {
 public:
  static void SetUpTestSuite() { worker_ = makeTestWorker(); }
  static void TearDownTestSuite() { worker_.reset(); }
  void SetUp() override { ASSERT_NE(worker_, nullptr) << "no device could be made"; }

  // Runs fn on the suite's device thread (free helpers of a test file may call it too).
  static compute::ComputeWorker& worker() { return *worker_; }
  template <class F>
  static auto onGl(F&& fn) {
    return worker_->call(std::forward<F>(fn));
  }

 private:
  static inline std::unique_ptr<compute::ComputeWorker> worker_;
};

// Fixture for tests of what only the GL device has (GLSL compilation, GL state): a GL worker
// whatever the backend the run is for.
class GlOnlyTest : public ::testing::Test {
 public:
  static void SetUpTestSuite() { worker_ = std::make_unique<gl::GlWorker>(); }
  static void TearDownTestSuite() { worker_.reset(); }
  void SetUp() override { ASSERT_NE(worker_, nullptr) << "no GL context could be made"; }
  template <class F>
  static auto onGl(F&& fn) {
    return worker_->call(std::forward<F>(fn));
  }

 private:
  static inline std::unique_ptr<gl::GlWorker> worker_;
};

}  // namespace hf::test
