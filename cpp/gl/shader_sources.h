// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The GLSL sources of shaders/, embedded at build time (cmake/embed_shaders.cmake).
#include <string>
#include <vector>

namespace hf::gl {

struct EmbeddedShader {
  const char* file;    // e.g. "jacobi.comp"
  const char* source;  // the file's text
};

const std::vector<EmbeddedShader>& embeddedShaders();

// The text of an embedded shader file; throws hf::Error naming the file if it is not embedded.
const std::string& shaderSource(const std::string& file);

}  // namespace hf::gl
