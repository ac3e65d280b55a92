// SPDX-License-Identifier: GPL-3.0-or-later
// What ComputeProgram::dispatch does after the dispatch: the barrier bits its program's writes
// need (not GL_ALL_BARRIER_BITS), the dispatch and sync counters, and GL error checks only in
// the debug mode (HAPTICFLUID_GL_DEBUG=1), which then names the stage.
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>

#include <string>

#include "common/error.h"
#include "compute/compute_program.h"
#include "gl/gl_program.h"
#include "gl/gl_check.h"
#include "gl/gl_device.h"
#include "compute/storage_buffer.h"
#include "test_util.h"

namespace hf::gl {
using namespace hf::compute;  // the device interface these GL tests exercise
namespace {

using hf::test::contains;

const char* kImageStage =
    "layout(local_size_x = 1) in;\n"
    "layout(r32f, binding = 0) uniform image3D u_img;\n"
    "void main() { imageStore(u_img, ivec3(0), vec4(1.0)); }\n";
const char* kBufferStage =
    "layout(local_size_x = 1) in;\n"
    "layout(std430, binding = 0) buffer B { float b[]; };\n"
    "void main() { b[gl_GlobalInvocationID.x] = 2.0; }\n";

// Restores the debug mode a test changed.
struct DebugModeGuard {
  bool old = debugMode();
  ~DebugModeGuard() { setDebugMode(old); }
};

TEST(GlDispatch, BarrierBitsFollowWhatTheProgramWrites) {
  GlWorker worker;
  worker.call([] {
    GlProgram image("image.comp", kImageStage, {});
    const unsigned image_bits =
        GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT;
    EXPECT_EQ(image.barrierBits(), image_bits);
    GlProgram buffer("buffer.comp", kBufferStage, {});
    EXPECT_EQ(buffer.barrierBits(), static_cast<unsigned>(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT));
  });
}

TEST(GlDispatch, CountersCountDispatchesAndReadBacks) {
  GlWorker worker;
  worker.call([] {
    GlProgram program("buffer.comp", kBufferStage, {});
    StorageBuffer buf(4 * sizeof(float), "counted");
    buf.bind(0);
    const DispatchCounters before = dispatchCounters();
    program.dispatch({4, 1, 1});
    program.dispatch({4, 1, 1});
    float out[4] = {0, 0, 0, 0};
    buf.download(out, sizeof(out));  // also shows the barrier made the writes visible
    const DispatchCounters after = dispatchCounters();
    EXPECT_EQ(after.dispatches - before.dispatches, 2u);
    EXPECT_EQ(after.syncs - before.syncs, 1u);
    for (float v : out) EXPECT_EQ(v, 2.0f);
  });
}

// A dispatch after an invalid call (an image unit far past any limit): the flag is raised.
void provokeErrorAndDispatch(GlProgram& program) {
  glBindImageTexture(100000, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32F);
  program.dispatch({1, 1, 1});
}

TEST(GlDispatch, ErrorsAreCheckedPerDispatchOnlyInDebugMode) {
  DebugModeGuard guard;
  setDebugMode(false);
  {
    GlWorker worker;
    worker.call([] {
      GlProgram program("buffer.comp", kBufferStage, {});
      StorageBuffer buf(sizeof(float), "b");
      buf.bind(0);
      EXPECT_NO_THROW(provokeErrorAndDispatch(program));            // not checked per dispatch...
      EXPECT_THROW(checkGl("the step's read-back"), GlError);     // ...but at the next check
    });
  }
  setDebugMode(true);
  GlWorker debug_worker;  // made in debug mode: a debug context with the KHR_debug callback
  debug_worker.call([] {
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    EXPECT_NE(flags & GL_CONTEXT_FLAG_DEBUG_BIT, 0);
    GlProgram program("buffer.comp", kBufferStage, {});
    StorageBuffer buf(sizeof(float), "b");
    buf.bind(0);
    try {
      provokeErrorAndDispatch(program);
      ADD_FAILURE() << "the error passed the debug-mode dispatch";
    } catch (const GlError& e) {
      EXPECT_TRUE(contains(e.what(), "dispatching buffer.comp")) << e.what();
      EXPECT_TRUE(contains(e.what(), "GL_INVALID_VALUE")) << e.what();
    }
    EXPECT_NO_THROW(program.dispatch({1, 1, 1}));  // the check left the flags clean
  });
}

}  // namespace
}  // namespace hf::gl
