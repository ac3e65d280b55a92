// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/texture3d.h"

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

FormatInfo formatInfo(TexelFormat f) {
  switch (f) {
    case TexelFormat::R32F: return {GL_R32F, GL_RED, GL_FLOAT, false};
    case TexelFormat::RGBA32F: return {GL_RGBA32F, GL_RGBA, GL_FLOAT, false};
    case TexelFormat::R8UI: return {GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, true};
  }
  return {GL_R32F, GL_RED, GL_FLOAT, false};
}

}  // namespace

std::size_t texelBytes(TexelFormat format) {
  switch (format) {
    case TexelFormat::R32F: return 4;
    case TexelFormat::RGBA32F: return 16;
    case TexelFormat::R8UI: return 1;
  }
  return 4;
}

Texture3D::Texture3D(const glm::ivec3& size, TexelFormat format, const std::string& label)
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
    release();
    throw;
  }
}

Texture3D::~Texture3D() { release(); }

void Texture3D::release() {
  if (id_ != 0) glDeleteTextures(1, &id_);
  id_ = 0;
}

Texture3D::Texture3D(Texture3D&& o) noexcept
    : id_(o.id_), size_(o.size_), format_(o.format_), label_(std::move(o.label_)) {
  o.id_ = 0;
}

Texture3D& Texture3D::operator=(Texture3D&& o) noexcept {
  if (this != &o) {
    release();
    id_ = o.id_;
    size_ = o.size_;
    format_ = o.format_;
    label_ = std::move(o.label_);
    o.id_ = 0;
  }
  return *this;
}

std::size_t Texture3D::bytesPerTexel() const { return texelBytes(format_); }

void Texture3D::bindSampler(unsigned unit) const { glBindTextureUnit(unit, id_); }

void Texture3D::bindImage(unsigned unit, Access access) const {
  const GLenum gl_access = access == Access::Read ? GL_READ_ONLY : access == Access::Write ? GL_WRITE_ONLY : GL_READ_WRITE;
  glBindImageTexture(unit, id_, 0, GL_TRUE, 0, gl_access, formatInfo(format_).internal);
}

void Texture3D::clear() {
  const FormatInfo fi = formatInfo(format_);
  glClearTexImage(id_, 0, fi.format, fi.type, nullptr);
  checkGl("clearing texture '" + label_ + "'");
}

void Texture3D::download(void* dst, std::size_t bytes) const {
  if (bytes != texels() * bytesPerTexel()) throw Error("download of '" + label_ + "': wrong buffer size");
  const FormatInfo fi = formatInfo(format_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  countSync();  // waits for the GPU to finish what wrote it
  // In z-slabs of at most kMaxReadBytes: GL sizes are GLsizei, and 2 GiB fields exist.
  const std::size_t slice = static_cast<std::size_t>(size_.x) * size_.y * bytesPerTexel();
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

void Texture3D::upload(const void* src, std::size_t bytes) {
  if (bytes != texels() * bytesPerTexel()) throw Error("upload to '" + label_ + "': wrong buffer size");
  const FormatInfo fi = formatInfo(format_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage3D(id_, 0, 0, 0, 0, size_.x, size_.y, size_.z, fi.format, fi.type, src);
  checkGl("uploading texture '" + label_ + "'");
}

}  // namespace hf::gl
