// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/storage_buffer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include "common/error.h"
#include "gl/gl_check.h"

namespace hf::gl {

std::size_t maxStorageBlockBytes() {
  GLint64 limit = 0;
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
  return static_cast<std::size_t>(limit > 0 ? limit : 0);
}

StorageBuffer::StorageBuffer(std::size_t bytes, const std::string& label) : bytes_(bytes), label_(label) {
  // Every storage buffer is bound whole to one block; past this limit the spec leaves the
  // shader's accesses undefined (llvmpipe writes past it without an error), so refuse first.
  const std::size_t limit = maxStorageBlockBytes();
  if (limit > 0 && bytes > limit) {
    throw GlError("buffer '" + label + "' needs " + std::to_string(bytes >> 20) + " MiB but this device's " +
                  "GL_MAX_SHADER_STORAGE_BLOCK_SIZE is " + std::to_string(limit >> 20) +
                  " MiB: lower the resolution");
  }
  glCreateBuffers(1, &id_);
  glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  try {
    checkGl("allocating buffer '" + label + "'");
  } catch (...) {
    glDeleteBuffers(1, &id_);
    throw;
  }
}

StorageBuffer::~StorageBuffer() {
  if (id_ != 0) glDeleteBuffers(1, &id_);
}

void StorageBuffer::bind(unsigned binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

void StorageBuffer::clear() {
  glClearNamedBufferData(id_, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  checkGl("clearing buffer '" + label_ + "'");
}

void StorageBuffer::download(void* dst, std::size_t bytes, std::size_t offset) const {
  if (offset + bytes > bytes_) throw Error("read of buffer '" + label_ + "' past its end");
  glGetNamedBufferSubData(id_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), dst);
  countSync();  // waits for the GPU to finish what wrote it
  checkGl("reading back buffer '" + label_ + "'");
}

void StorageBuffer::upload(const void* src, std::size_t bytes, std::size_t offset) {
  if (offset + bytes > bytes_) throw Error("write to buffer '" + label_ + "' past its end");
  glNamedBufferSubData(id_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), src);
  checkGl("uploading buffer '" + label_ + "'");
}

}  // namespace hf::gl
