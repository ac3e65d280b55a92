// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// compute::StorageBuffer on GL: one shader storage buffer (RAII).
#include <cstddef>
#include <string>

#include "compute/device.h"

namespace hf::gl {

// GL_MAX_SHADER_STORAGE_BLOCK_SIZE of the current context (GL guarantees 128 MiB).
std::size_t maxStorageBlockBytes();

class GlBuffer final : public compute::BufferImpl {
 public:
  GlBuffer(std::size_t bytes, const std::string& label);
  ~GlBuffer() override;
  GlBuffer(const GlBuffer&) = delete;
  GlBuffer& operator=(const GlBuffer&) = delete;

  void bind(unsigned binding) const override;  // GL_SHADER_STORAGE_BUFFER binding point
  void clear() override;
  void download(void* dst, std::size_t bytes, std::size_t offset) const override;
  void upload(const void* src, std::size_t bytes, std::size_t offset) override;

 private:
  unsigned int id_ = 0;
  std::string label_;
};

}  // namespace hf::gl
