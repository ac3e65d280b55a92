// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_buffer.h"

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

GlBuffer::GlBuffer(std::size_t bytes, const std::string& label) : label_(label) {
  glCreateBuffers(1, &id_);
  glNamedBufferStorage(id_, static_cast<GLsizeiptr>(bytes), nullptr, GL_DYNAMIC_STORAGE_BIT);
  try {
    checkGl("allocating buffer '" + label + "'");
  } catch (...) {
    glDeleteBuffers(1, &id_);
    throw;
  }
}

GlBuffer::~GlBuffer() {
  if (id_ != 0) glDeleteBuffers(1, &id_);
}

void GlBuffer::bind(unsigned binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

void GlBuffer::clear() {
  glClearNamedBufferData(id_, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, nullptr);
  checkGl("clearing buffer '" + label_ + "'");
}

void GlBuffer::download(void* dst, std::size_t bytes, std::size_t offset) const {
  glGetNamedBufferSubData(id_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), dst);
  compute::countSync();  // waits for the GPU to finish what wrote it
  checkGl("reading back buffer '" + label_ + "'");
}

void GlBuffer::upload(const void* src, std::size_t bytes, std::size_t offset) {
  glNamedBufferSubData(id_, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), src);
  checkGl("uploading buffer '" + label_ + "'");
}

}  // namespace hf::gl
