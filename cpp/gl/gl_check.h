#pragma once
// Turns the GL error flag into an exception naming the stage that raised it.
#include <string>

namespace hf::gl {

// Throws hf::GlError("<stage>: GL_INVALID_OPERATION ...") if glGetError() reports anything.
void checkGl(const std::string& stage);

// Name of a GL error enum, e.g. "GL_OUT_OF_MEMORY".
const char* glErrorName(unsigned int code);

}  // namespace hf::gl
