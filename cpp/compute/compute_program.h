// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One compute kernel of shaders/ on the current device (RAII): on the GPU, the file compiled and
// linked with common.glsl prepended; on the CPU, the same file compiled into the module as C++.
// Uniforms are set by name (a name the kernel does not use is ignored, as GL ignores a uniform
// the compiler removed); images and buffers are bound by unit (Texture3D::bindImage,
// StorageBuffer::bind) before dispatch().
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "compute/device.h"

namespace hf::compute {

class ComputeProgram {
 public:
  // `file` names a kernel in shaders/ (e.g. "jacobi.comp"); `defines` become #define lines.
  ComputeProgram(const std::string& file, const Defines& defines);
  ~ComputeProgram();
  ComputeProgram(const ComputeProgram&) = delete;
  ComputeProgram& operator=(const ComputeProgram&) = delete;

  const std::string& name() const { return name_; }
  glm::ivec3 localSize() const { return impl_->localSize(); }
  int imageUnits() const { return impl_->imageUnits(); }  // distinct image units it uses

  void set(const char* uniform, int v) { impl_->setInt(uniform, v); }
  void set(const char* uniform, unsigned v) { impl_->setUint(uniform, v); }
  void set(const char* uniform, float v) { impl_->setFloat(uniform, v); }
  void set(const char* uniform, const glm::ivec3& v) { impl_->setIVec3(uniform, v); }
  void set(const char* uniform, const glm::vec3& v) { impl_->setVec3(uniform, v); }
  void set(const char* uniform, const glm::mat4& v) { impl_->setMat4(uniform, v); }

  // Runs the kernel over `invocations` (each axis covered: the GPU rounds up to whole workgroups,
  // and every kernel ignores the invocations past its grid); its writes are visible to the next
  // stage and to read-backs.
  void dispatch(const glm::ivec3& invocations) { impl_->dispatch(invocations); }

  // Each (program, invocations) of `series` dispatched in turn, the images and buffers bound as
  // they are now: the same result, which a device may compute in one pass
  // (ProgramImpl::dispatchSeries).
  static void dispatchSeries(const std::vector<std::pair<ComputeProgram*, glm::ivec3>>& series) {
    std::vector<ProgramImpl::SeriesDispatch> d;
    d.reserve(series.size());
    for (const auto& [program, invocations] : series) d.push_back({program->impl_.get(), invocations});
    if (!d.empty()) d.front().program->dispatchSeries(d);
  }

 private:
  std::string name_;
  std::unique_ptr<ProgramImpl> impl_;
};

}  // namespace hf::compute
