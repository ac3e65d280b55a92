// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// compute::ComputeProgram on GL: one compiled and linked GLSL compute program (RAII), built from
// an embedded shaders/ file with common.glsl prepended. Compile and link errors throw
// hf::GlError quoting the log with each line reported as "<file>:<line>".
#include <glm/glm.hpp>
#include <string>

#include "compute/device.h"
#include <unordered_map>
#include <utility>
#include <vector>

namespace hf::gl {

using compute::Defines;

// GL 4.5's guaranteed minimum of GL_MAX_IMAGE_UNITS and GL_MAX_COMPUTE_IMAGE_UNIFORMS: a
// program binding more image units is refused at link time, whatever this device allows.
inline constexpr int kGuaranteedImageUnits = 8;

class GlProgram final : public compute::ProgramImpl {
 public:
  // `file` names a shader in shaders/ (e.g. "jacobi.comp"); `defines` become #define lines.
  GlProgram(const std::string& file, const Defines& defines);
  // Builds from explicit source text (tests use it to check the error reporting).
  GlProgram(const std::string& file, const std::string& source, const Defines& defines);
  ~GlProgram() override;
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  const std::string& name() const { return name_; }
  glm::ivec3 localSize() const override { return local_size_; }
  int imageUnits() const override { return image_units_; }  // distinct image units its active images use
  unsigned barrierBits() const { return barrier_bits_; }  // glMemoryBarrier bits after a dispatch

  void setInt(const char* uniform, int v) override;
  void setUint(const char* uniform, unsigned v) override;
  void setFloat(const char* uniform, float v) override;
  void setIVec3(const char* uniform, const glm::ivec3& v) override;
  void setVec3(const char* uniform, const glm::vec3& v) override;
  void setMat4(const char* uniform, const glm::mat4& v) override;

  // Dispatches enough workgroups to cover `invocations` threads, then a memory barrier with the
  // bits this program's writes need (images and/or storage buffers, see barrierBits()) so the
  // next stage and read-backs see them; in debug mode (gl_check.h) checks GL errors naming it.
  void dispatch(const glm::ivec3& invocations) override;

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
