// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One shader storage buffer (RAII).
#include <cstddef>
#include <string>

namespace hf::gl {

// GL_MAX_SHADER_STORAGE_BLOCK_SIZE of the current context (GL guarantees 128 MiB).
std::size_t maxStorageBlockBytes();

class StorageBuffer {
 public:
  // Throws hf::GlError naming `label` before allocating when `bytes` exceeds
  // maxStorageBlockBytes(): a shader could not address the whole buffer.
  StorageBuffer(std::size_t bytes, const std::string& label);
  ~StorageBuffer();
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  std::size_t bytes() const { return bytes_; }
  void bind(unsigned binding) const;  // GL_SHADER_STORAGE_BUFFER binding point
  void clear();                       // every byte to zero
  void download(void* dst, std::size_t bytes, std::size_t offset = 0) const;
  void upload(const void* src, std::size_t bytes, std::size_t offset = 0);

 private:
  unsigned int id_ = 0;
  std::size_t bytes_ = 0;
  std::string label_;
};

}  // namespace hf::gl
