// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One storage buffer of the current device (RAII).
#include <cstddef>
#include <memory>
#include <string>

#include "compute/device.h"

namespace hf::compute {

// The largest storage buffer the current device's programs can address (GL:
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE, at least 128 MiB).
std::size_t maxStorageBlockBytes();

class StorageBuffer {
 public:
  // Throws hf::GlError naming `label` before allocating when `bytes` exceeds
  // maxStorageBlockBytes(): a program could not address the whole buffer. Starts zeroed on the
  // CPU, undefined on the GPU until written or cleared.
  StorageBuffer(std::size_t bytes, const std::string& label);
  ~StorageBuffer();
  StorageBuffer(const StorageBuffer&) = delete;
  StorageBuffer& operator=(const StorageBuffer&) = delete;

  std::size_t bytes() const { return bytes_; }
  void bind(unsigned binding) const { impl_->bind(binding); }  // the storage block binding point
  void clear() { impl_->clear(); }                             // every byte to zero
  void download(void* dst, std::size_t bytes, std::size_t offset = 0) const;
  void upload(const void* src, std::size_t bytes, std::size_t offset = 0);

 private:
  std::unique_ptr<BufferImpl> impl_;
  std::size_t bytes_ = 0;
  std::string label_;
};

}  // namespace hf::compute
