// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_texture.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>

#include "common/error.h"
#include "gl/gl_check.h"

namespace hf::gl {
namespace {

constexpr std::size_t kMaxReadBytes = std::size_t(1) << 30;  // per glGetTextureSubImage call

struct FormatInfo {
  GLenum internal, format, type;
  bool integer;
};

FormatInfo formatInfo(compute::TexelFormat f) {
  switch (f) {
    case compute::TexelFormat::R32F: return {GL_R32F, GL_RED, GL_FLOAT, false};
    case compute::TexelFormat::RGBA32F: return {GL_RGBA32F, GL_RGBA, GL_FLOAT, false};
    case compute::TexelFormat::R8UI: return {GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, true};
  }
  return {GL_R32F, GL_RED, GL_FLOAT, false};
}

}  // namespace

GlTexture::GlTexture(const glm::ivec3& size, compute::TexelFormat format, const std::string& label)
    : size_(size), format_(format), label_(label) {
  const FormatInfo fi = formatInfo(format);
  glCreateTextures(GL_TEXTURE_3D, 1, &id_);
  glTextureStorage3D(id_, 1, fi.internal, size.x, size.y, size.z);
  const GLint filter = fi.integer ? GL_NEAREST : GL_LINEAR;
  glTextureParameteri(id_, GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(id_, GL_TEXTURE_MAG_FILTER, filter);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id_, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  try {
    checkGl("allocating texture '" + label + "'");
    clear();
  } catch (...) {
    glDeleteTextures(1, &id_);
    throw;
  }
}

GlTexture::~GlTexture() {
  if (id_ != 0) glDeleteTextures(1, &id_);
}

void GlTexture::bindImage(unsigned unit, compute::Access access) const {
  const GLenum gl_access = access == compute::Access::Read ? GL_READ_ONLY : access == compute::Access::Write ? GL_WRITE_ONLY : GL_READ_WRITE;
  glBindImageTexture(unit, id_, 0, GL_TRUE, 0, gl_access, formatInfo(format_).internal);
}

void GlTexture::clear() {
  const FormatInfo fi = formatInfo(format_);
  glClearTexImage(id_, 0, fi.format, fi.type, nullptr);
  checkGl("clearing texture '" + label_ + "'");
}

void GlTexture::download(void* dst, std::size_t bytes) const {
  static_cast<void>(bytes);  // checked by compute::Texture3D
  const FormatInfo fi = formatInfo(format_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  compute::countSync();  // waits for the GPU to finish what wrote it
  // In z-slabs of at most kMaxReadBytes: GL sizes are GLsizei, and 2 GiB fields exist.
  const std::size_t slice = static_cast<std::size_t>(size_.x) * size_.y * compute::texelBytes(format_);
  const int slab = static_cast<int>(std::max<std::size_t>(1, kMaxReadBytes / slice));
  auto* out = static_cast<unsigned char*>(dst);
  for (int z = 0; z < size_.z; z += slab) {
    const int depth = std::min(slab, size_.z - z);
    const std::size_t n = slice * static_cast<std::size_t>(depth);
    glGetTextureSubImage(id_, 0, 0, 0, z, size_.x, size_.y, depth, fi.format, fi.type, static_cast<GLsizei>(n),
                         out + slice * static_cast<std::size_t>(z));
  }
  checkGl("reading back texture '" + label_ + "'");
}

void GlTexture::upload(const void* src, std::size_t bytes) {
  static_cast<void>(bytes);  // checked by compute::Texture3D
  const FormatInfo fi = formatInfo(format_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage3D(id_, 0, 0, 0, 0, size_.x, size_.y, size_.z, fi.format, fi.type, src);
  checkGl("uploading texture '" + label_ + "'");
}

}  // namespace hf::gl
