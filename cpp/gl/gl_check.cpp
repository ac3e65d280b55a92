#include "gl/gl_check.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include "common/error.h"

namespace hf::gl {

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

}  // namespace hf::gl
