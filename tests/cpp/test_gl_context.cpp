// SPDX-License-Identifier: GPL-3.0-or-later
// GlWorker / EglContext: a context on the worker's thread, what it reports, and how device
// requests (argument or HAPTICFLUID_EGL_DEVICE) are honoured or rejected.
#include <EGL/egl.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>

#include "common/error.h"
#include "gl/egl_context.h"
#include "gl/gl_device.h"
#include "test_util.h"

namespace hf::gl {
using namespace hf::compute;  // the device interface these GL tests exercise
namespace {

using hf::test::contains;
using hf::test::EnvGuard;

constexpr const char* kEnv = "HAPTICFLUID_EGL_DEVICE";

// "4.5 (Core Profile) Mesa 22.3.6" -> {4, 5}
std::pair<int, int> parseVersion(const std::string& v) {
  int major = 0, minor = 0;
  if (std::sscanf(v.c_str(), "%d.%d", &major, &minor) != 2) return {0, 0};
  return {major, minor};
}

TEST(GlContext, WorkerMakesA43CoreContextOnItsOwnThread) {
  EnvGuard env(kEnv, nullptr);
  GlWorker worker;
  const ContextInfo& info = worker.info();
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_FALSE(info.vendor.empty());
  const auto [major, minor] = parseVersion(info.version);
  EXPECT_GE(major * 10 + minor, 43) << "GL_VERSION '" << info.version << "'";
  EXPECT_TRUE(info.platform == "device" || info.platform == "surfaceless") << info.platform;
  EXPECT_EQ(info.platform == "device", info.device_index >= 0);
  EXPECT_GE(info.max_3d_texture_size, 2048);  // the GL 4.x minimum

  struct OnThread {
    std::thread::id id;
    bool has_context;
    GLint major, minor, profile;
    std::string renderer;
  };
  const OnThread seen = worker.call([] {
    OnThread s{};
    s.id = std::this_thread::get_id();
    s.has_context = eglGetCurrentContext() != EGL_NO_CONTEXT;
    glGetIntegerv(GL_MAJOR_VERSION, &s.major);
    glGetIntegerv(GL_MINOR_VERSION, &s.minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &s.profile);
    s.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return s;
  });
  EXPECT_NE(seen.id, std::this_thread::get_id()) << "GL work must run on the worker's thread";
  EXPECT_TRUE(seen.has_context);
  EXPECT_GE(seen.major * 10 + seen.minor, 43);
  EXPECT_NE(seen.profile & GL_CONTEXT_CORE_PROFILE_BIT, 0);
  EXPECT_EQ(seen.renderer, info.renderer);
  // The calling thread has no context of its own.
  EXPECT_EQ(eglGetCurrentContext(), EGL_NO_CONTEXT);
}

TEST(GlContext, CallReturnsValuesAndRethrowsTheJobsExceptionType) {
  GlWorker worker;
  EXPECT_EQ(worker.call([] { return 6 * 7; }), 42);
  EXPECT_THROW(worker.call([] { throw InvalidArgument("bad"); }), InvalidArgument);
  EXPECT_THROW(worker.call([]() -> int { throw std::out_of_range("x"); }), std::out_of_range);
  // The worker survives a throwing job.
  EXPECT_EQ(worker.call([] { return eglGetCurrentContext() != EGL_NO_CONTEXT; }), true);
}

TEST(GlContext, TwoWorkersHaveSeparateContexts) {
  GlWorker a;
  GlWorker b;
  const GLuint name = a.call([] {
    GLuint t = 0;
    glCreateTextures(GL_TEXTURE_3D, 1, &t);
    return t;
  });
  ASSERT_NE(name, 0u);
  EXPECT_EQ(a.call([name] { return glIsTexture(name) == GL_TRUE; }), true);
  // The contexts share nothing: b does not know a's texture name.
  EXPECT_EQ(b.call([name] { return glIsTexture(name) == GL_TRUE; }), false);
  EXPECT_NE(a.call([] { return eglGetCurrentContext(); }), b.call([] { return eglGetCurrentContext(); }));
  a.call([name] { glDeleteTextures(1, &name); });
}

TEST(GlContext, SoftwareRequestGivesASoftwareRenderer) {
  EnvGuard env(kEnv, nullptr);
  GlWorker worker("software");
  EXPECT_TRUE(worker.info().software) << worker.info().renderer;
  // A software device's memory is the host's: known and non-zero.
  EXPECT_GT(worker.info().memory_bytes, 0u);
}

TEST(GlContext, EnvironmentVariableSelectsTheDevice) {
  EnvGuard env(kEnv, "software");
  GlWorker worker;  // empty request: the environment decides
  EXPECT_TRUE(worker.info().software) << worker.info().renderer;
}

TEST(GlContext, ExplicitRequestOverridesTheEnvironment) {
  EnvGuard env(kEnv, "banana");
  EXPECT_THROW(GlWorker{}, InvalidArgument);        // the environment's malformed value is used...
  EXPECT_NO_THROW(GlWorker worker("software"));     // ...unless the caller names a device
}

TEST(GlContext, DeviceNumberPicksThatDevice) {
  EnvGuard env(kEnv, nullptr);
  const std::string devices = listDevices();
  if (contains(devices, "no EGL devices enumerated")) GTEST_SKIP() << "no enumerable EGL device";
  GlWorker worker("0");
  EXPECT_EQ(worker.info().platform, "device");
  EXPECT_EQ(worker.info().device_index, 0);
}

TEST(GlContext, DeviceNumberJustPastTheLastThrows) {
  EnvGuard env(kEnv, nullptr);
  // listDevices() prints one "  <index>: ..." line per enumerated device.
  const std::string devices = listDevices();
  const int count = contains(devices, "no EGL devices enumerated")
                        ? 0
                        : static_cast<int>(std::count(devices.begin(), devices.end(), '\n'));
  EXPECT_THROW(GlWorker(std::to_string(count)), InvalidArgument) << devices;
  if (count > 0) {
    EXPECT_NO_THROW(GlWorker(std::to_string(count - 1)));
  }
}

class MalformedRequest : public ::testing::TestWithParam<const char*> {};

TEST_P(MalformedRequest, ThrowsInvalidArgumentListingTheDevices) {
  EnvGuard env(kEnv, nullptr);
  const std::string request = GetParam();
  const std::string devices = listDevices();
  ASSERT_FALSE(devices.empty());
  try {
    GlWorker worker(request);
    FAIL() << "request '" << request << "' was accepted (" << worker.info().renderer << ")";
  } catch (const InvalidArgument& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, request)) << msg;
    EXPECT_TRUE(contains(msg, "devices found")) << msg;
    EXPECT_TRUE(contains(msg, devices)) << msg << "\n--- expected the list:\n" << devices;
    EXPECT_TRUE(contains(msg, kEnv)) << msg;
  }
}

TEST_P(MalformedRequest, ThrowsFromTheEnvironmentToo) {
  EnvGuard env(kEnv, GetParam());
  EXPECT_THROW(GlWorker{}, InvalidArgument);
}

INSTANTIATE_TEST_SUITE_P(Requests, MalformedRequest,
                         ::testing::Values("banana", "99", "-1", "0x1", "1.5", "software2", " "));

}  // namespace
}  // namespace hf::gl
