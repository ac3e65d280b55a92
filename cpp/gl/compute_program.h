// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One compiled and linked GLSL compute program (RAII), built from an embedded shaders/ file
// with common.glsl prepended. Compile and link errors throw hf::GlError quoting the log with
// each line reported as "<file>:<line>".
#include <glm/glm.hpp>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hf::gl {

using Defines = std::vector<std::pair<std::string, std::string>>;

// GL 4.5's guaranteed minimum of GL_MAX_IMAGE_UNITS and GL_MAX_COMPUTE_IMAGE_UNIFORMS: a
// program binding more image units is refused at link time, whatever this device allows.
inline constexpr int kGuaranteedImageUnits = 8;

class ComputeProgram {
 public:
  // `file` names a shader in shaders/ (e.g. "jacobi.comp"); `defines` become #define lines.
  ComputeProgram(const std::string& file, const Defines& defines);
  // Builds from explicit source text (tests use it to check the error reporting).
  ComputeProgram(const std::string& file, const std::string& source, const Defines& defines);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  const std::string& name() const { return name_; }
  glm::ivec3 localSize() const { return local_size_; }
  int imageUnits() const { return image_units_; }  // distinct image units its active images use
  unsigned barrierBits() const { return barrier_bits_; }  // glMemoryBarrier bits after a dispatch

  // Binds the program; the setters below act on the bound program.
  void use() const;
  void set(const char* uniform, int v);
  void set(const char* uniform, unsigned v);
  void set(const char* uniform, float v);
  void set(const char* uniform, const glm::ivec3& v);
  void set(const char* uniform, const glm::vec3& v);
  void set(const char* uniform, const glm::mat4& v);

  // Dispatches enough workgroups to cover `invocations` threads, then a memory barrier with the
  // bits this program's writes need (images and/or storage buffers, see barrierBits()) so the
  // next stage and read-backs see them; in debug mode (gl_check.h) checks GL errors naming it.
  void dispatch(const glm::ivec3& invocations) const;

 private:
  int location(const char* uniform);

  std::string name_;
  unsigned int id_ = 0;
  glm::ivec3 local_size_{1};
  int image_units_ = 0;
  unsigned barrier_bits_ = 0;
  std::unordered_map<std::string, int> locations_;
};

// The #line-tagged full source given to the compiler, and the file of each source string.
std::string composeSource(const std::string& stage_source, const Defines& defines);

// Rewrites a driver's info log so "0:12(5): error" (Mesa) or "0(12) : error" (NVIDIA) read
// "<file>:12: error", where source string 1 is common.glsl and 2 the stage file.
std::string annotateLog(const std::string& log, const std::string& stage_file);

}  // namespace hf::gl
