// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/storage_buffer.h"

#include "common/error.h"

namespace hf::compute {

std::size_t maxStorageBlockBytes() { return currentDevice().info().max_storage_block_bytes; }

StorageBuffer::StorageBuffer(std::size_t bytes, const std::string& label) : bytes_(bytes), label_(label) {
  // Every storage buffer is bound whole to one block; past this limit GL leaves the shader's
  // accesses undefined (llvmpipe writes past it without an error), so refuse first.
  const std::size_t limit = maxStorageBlockBytes();
  if (limit > 0 && bytes > limit) {
    throw GlError("buffer '" + label + "' needs " + std::to_string(bytes >> 20) + " MiB but this device's " +
                  "largest storage block (GL_MAX_SHADER_STORAGE_BLOCK_SIZE) is " + std::to_string(limit >> 20) +
                  " MiB: lower the resolution");
  }
  impl_ = currentDevice().makeBuffer(bytes, label);
}

StorageBuffer::~StorageBuffer() = default;

void StorageBuffer::download(void* dst, std::size_t bytes, std::size_t offset) const {
  if (offset > bytes_ || bytes > bytes_ - offset) throw Error("read of buffer '" + label_ + "' past its end");
  impl_->download(dst, bytes, offset);
}

void StorageBuffer::upload(const void* src, std::size_t bytes, std::size_t offset) {
  if (offset > bytes_ || bytes > bytes_ - offset) throw Error("write to buffer '" + label_ + "' past its end");
  impl_->upload(src, bytes, offset);
}

}  // namespace hf::compute
