// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_check.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <atomic>
#include <cstdlib>
#include <cstring>

#include "common/error.h"

namespace hf::gl {
namespace {

std::atomic<int>& debugFlag() {  // -1 = not read from the environment yet
  static std::atomic<int> flag{-1};
  return flag;
}


// KHR_debug error messages of this thread's context since the last checkDebug().
thread_local std::string t_debug_errors;

void GLAPIENTRY onDebugMessage(GLenum /*source*/, GLenum type, GLuint /*id*/, GLenum severity, GLsizei length,
                               const GLchar* message, const void* /*user*/) {
  if (type != GL_DEBUG_TYPE_ERROR && severity != GL_DEBUG_SEVERITY_HIGH) return;
  if (!t_debug_errors.empty()) t_debug_errors += "; ";
  t_debug_errors += length >= 0 ? std::string(message, static_cast<std::size_t>(length)) : std::string(message);
}

}  // namespace

const char* glErrorName(unsigned int code) {
  switch (code) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    default: return "unknown GL error";
  }
}

void checkGl(const std::string& stage) {
  GLenum first = glGetError();
  if (first == GL_NO_ERROR) return;
  std::string msg = stage + ": " + glErrorName(first);
  // Drain the remaining flags so the next check starts clean.
  for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError()) {
    msg += std::string(", ") + glErrorName(e);
  }
  if (first == GL_OUT_OF_MEMORY) {
    msg += " (the GPU ran out of memory: lower the resolution)";
  }
  throw GlError(msg);
}

bool debugMode() {
  int f = debugFlag().load();
  if (f < 0) {
    const char* env = std::getenv(kGlDebugEnv);
    f = (env != nullptr && std::strcmp(env, "1") == 0) ? 1 : 0;
    debugFlag().store(f);
  }
  return f == 1;
}

void setDebugMode(bool on) { debugFlag().store(on ? 1 : 0); }

void installDebugOutput() {
  glEnable(GL_DEBUG_OUTPUT);
  glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // the callback runs inside the failing call
  glDebugMessageCallback(onDebugMessage, nullptr);
  glGetError();  // a driver without the callback must not fail the first check
}

void checkDebug(const std::string& stage) {
  if (!debugMode()) return;
  std::string messages;
  messages.swap(t_debug_errors);
  try {
    checkGl(stage);
  } catch (const GlError& e) {
    throw GlError(std::string(e.what()) + (messages.empty() ? "" : " (" + messages + ")"));
  }
  if (!messages.empty()) throw GlError(stage + ": " + messages);
}

}  // namespace hf::gl
