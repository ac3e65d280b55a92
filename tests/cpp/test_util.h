// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The GL fixture shared by the GoogleTest files of the GL layers (not a test itself: the CMake
// globs take only *.cpp), and the GL-free helpers of test_common.h.
#include <gtest/gtest.h>

#include <memory>
#include <utility>

#include "gl/gl_worker.h"
#include "test_common.h"

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

}  // namespace hf::test
