// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_program.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <regex>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "gl/gl_check.h"
#include "gl/shader_sources.h"

namespace hf::gl {
namespace {

constexpr const char* kCommonFile = "common.glsl";
// Line numbers the parts of the composed source are compiled with. Mesa reports errors found
// after parsing (undeclared names, type mismatches) with source string 0 whatever #line set,
// so the part is told from the line's range; the source string number only breaks ties.
constexpr long kCommonLineBase = 100000;    // common.glsl line n is compiled as 100000 + n
constexpr long kPreambleLineBase = 200000;  // the n-th #define line is compiled as 200000 + n

// The info log of a shader (glGetShaderiv/InfoLog) or program (glGetProgramiv/InfoLog).
template <class GetIv, class GetLog>
std::string infoLog(GLuint id, GetIv get_iv, GetLog get_log) {
  GLint len = 0;
  get_iv(id, GL_INFO_LOG_LENGTH, &len);
  std::string log(static_cast<std::size_t>(len > 0 ? len : 1), '\0');
  get_log(id, len, nullptr, log.data());
  return log.c_str();
}

// GL_IMAGE_1D .. GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY: the image uniform types (GL 4.2),
// one contiguous range of enums.
bool isImageType(GLenum type) { return type >= 0x904C && type <= 0x906C; }

// Distinct image units the program's active image uniforms are bound to.
int countImageUnits(GLuint program) {
  GLint count = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  std::vector<GLint> units;
  for (GLint i = 0; i < count; ++i) {
    const GLenum props[] = {GL_TYPE, GL_LOCATION};
    GLint values[2] = {0, -1};
    glGetProgramResourceiv(program, GL_UNIFORM, static_cast<GLuint>(i), 2, props, 2, nullptr, values);
    if (!isImageType(static_cast<GLenum>(values[0])) || values[1] < 0) continue;
    GLint unit = -1;
    glGetUniformiv(program, values[1], &unit);
    if (std::find(units.begin(), units.end(), unit) == units.end()) units.push_back(unit);
  }
  return static_cast<int>(units.size());
}

// The barrier after a dispatch of `program`: what it may have written (images, storage
// buffers) made visible to the ways the engine reads them next: image loads/stores and
// texture fetches, storage-buffer access, and read-backs/clears (glGetTextureSubImage,
// glClearTexImage: TEXTURE_UPDATE; glGetNamedBufferSubData, glClearNamedBufferData:
// BUFFER_UPDATE). Nothing here feeds vertex, index, uniform, indirect or pixel-buffer reads.
GLbitfield barrierBitsFor(GLuint program, int image_units) {
  GLbitfield bits = 0;
  if (image_units > 0) {
    bits |= GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT;
  }
  GLint blocks = 0;
  glGetProgramInterfaceiv(program, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &blocks);
  if (blocks > 0) bits |= GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT;
  return bits;
}

}  // namespace

std::string composeSource(const std::string& stage_source, const Defines& defines) {
  std::string s = "#version 450 core\n";
  s += "#line " + std::to_string(kPreambleLineBase + 1) + " 0\n";
  for (const auto& [name, value] : defines) s += "#define " + name + " " + value + "\n";
  s += "#line " + std::to_string(kCommonLineBase + 1) + " 1\n";
  s += shaderSource(kCommonFile);
  s += "\n#line 1 2\n";
  s += stage_source;
  return s;
}

std::string annotateLog(const std::string& log, const std::string& stage_file) {
  static const std::regex mesa(R"(^(\d+):(\d+)\(\d+\))");
  static const std::regex nvidia(R"(^(\d+)\((\d+)\) ?)");  // "0(12) : error" -> "<file>:12: error"
  auto locate = [&](const std::string& source, long line) {
    if (line > kPreambleLineBase) return stage_file + " (preamble):" + std::to_string(line - kPreambleLineBase);
    if (line > kCommonLineBase) return std::string(kCommonFile) + ":" + std::to_string(line - kCommonLineBase);
    if (source == "1") return std::string(kCommonFile) + ":" + std::to_string(line);
    return stage_file + ":" + std::to_string(line);  // string 2, or Mesa's 0 after parsing
  };
  std::istringstream in(log);
  std::string line, out;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_search(line, m, mesa) || std::regex_search(line, m, nvidia)) {
      line = locate(m[1].str(), std::stol(m[2].str())) + line.substr(static_cast<std::size_t>(m.length(0)));
    }
    out += line + "\n";
  }
  return out;
}

GlProgram::GlProgram(const std::string& file, const Defines& defines)
    : GlProgram(file, shaderSource(file), defines) {}

GlProgram::GlProgram(const std::string& file, const std::string& source, const Defines& defines)
    : name_(file) {
  const std::string text = composeSource(source, defines);
  const char* ptr = text.c_str();
  GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  glShaderSource(shader, 1, &ptr, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw GlError("compiling " + file + " failed:\n" + annotateLog(log, file));
  }
  id_ = glCreateProgram();
  glAttachShader(id_, shader);
  glLinkProgram(id_);
  glDeleteShader(shader);  // flagged; freed with the program
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = infoLog(id_, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(id_);
    throw GlError("linking " + file + " failed:\n" + annotateLog(log, file));
  }
  GLint size[3] = {1, 1, 1};
  glGetProgramiv(id_, GL_COMPUTE_WORK_GROUP_SIZE, size);
  local_size_ = glm::ivec3(size[0], size[1], size[2]);
  image_units_ = countImageUnits(id_);
  barrier_bits_ = barrierBitsFor(id_, image_units_);
  try {
    checkGl("building " + file);
    if (image_units_ > kGuaranteedImageUnits) {
      throw GlError(file + " uses " + std::to_string(image_units_) + " image units, but GL 4.5 guarantees only " +
                    std::to_string(kGuaranteedImageUnits) +
                    " (GL_MAX_IMAGE_UNITS, GL_MAX_COMPUTE_IMAGE_UNIFORMS): split the stage or use a sampler");
    }
  } catch (...) {
    glDeleteProgram(id_);  // the destructor does not run for a constructor that throws
    throw;
  }
}

GlProgram::~GlProgram() {
  if (id_ != 0) glDeleteProgram(id_);
}

int GlProgram::location(const char* uniform) {
  auto it = locations_.find(uniform);
  if (it != locations_.end()) return it->second;
  const int loc = glGetUniformLocation(id_, uniform);  // -1 if optimised away: setting is a no-op
  locations_.emplace(uniform, loc);
  return loc;
}

void GlProgram::setInt(const char* uniform, int v) { glProgramUniform1i(id_, location(uniform), v); }
void GlProgram::setUint(const char* uniform, unsigned v) { glProgramUniform1ui(id_, location(uniform), v); }
void GlProgram::setFloat(const char* uniform, float v) { glProgramUniform1f(id_, location(uniform), v); }
void GlProgram::setIVec3(const char* uniform, const glm::ivec3& v) {
  glProgramUniform3i(id_, location(uniform), v.x, v.y, v.z);
}
void GlProgram::setVec3(const char* uniform, const glm::vec3& v) {
  glProgramUniform3f(id_, location(uniform), v.x, v.y, v.z);
}
void GlProgram::setMat4(const char* uniform, const glm::mat4& v) {
  glProgramUniformMatrix4fv(id_, location(uniform), 1, GL_FALSE, &v[0][0]);
}

void GlProgram::dispatch(const glm::ivec3& invocations) {
  const glm::ivec3 groups = (invocations + local_size_ - 1) / local_size_;
  glUseProgram(id_);
  glDispatchCompute(static_cast<GLuint>(groups.x), static_cast<GLuint>(groups.y), static_cast<GLuint>(groups.z));
  if (barrier_bits_ != 0) glMemoryBarrier(barrier_bits_);
  std::uint64_t launched = 1;
  for (int a = 0; a < 3; ++a) launched *= static_cast<std::uint64_t>(groups[a]) * static_cast<std::uint64_t>(local_size_[a]);
  compute::countDispatch(launched);
  checkDebug("dispatching " + name_);
}

}  // namespace hf::gl
