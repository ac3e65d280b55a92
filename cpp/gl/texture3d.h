// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One immutable-storage 3D texture (RAII). Float textures sample with trilinear filtering and
// clamp-to-edge; integer ones are fetched exactly.
#include <cstddef>
#include <glm/glm.hpp>
#include <string>

namespace hf::gl {

enum class TexelFormat { R32F, RGBA32F, R8UI };

// How a compute stage uses an image it binds (GL's image access, kept inside cpp/gl).
enum class Access { Read, Write, ReadWrite };

class Texture3D {
 public:
  Texture3D(const glm::ivec3& size, TexelFormat format, const std::string& label);
  ~Texture3D();
  Texture3D(Texture3D&& other) noexcept;
  Texture3D& operator=(Texture3D&& other) noexcept;
  Texture3D(const Texture3D&) = delete;
  Texture3D& operator=(const Texture3D&) = delete;

  glm::ivec3 size() const { return size_; }
  std::size_t texels() const { return static_cast<std::size_t>(size_.x) * size_.y * size_.z; }
  std::size_t bytesPerTexel() const;
  TexelFormat format() const { return format_; }
  const std::string& label() const { return label_; }

  void bindSampler(unsigned unit) const;
  void bindImage(unsigned unit, Access access) const;
  void clear();  // every texel to zero
  // Copies the whole texture into dst (texels() * bytesPerTexel() bytes), x fastest.
  void download(void* dst, std::size_t bytes) const;
  void upload(const void* src, std::size_t bytes);

 private:
  void release();

  unsigned int id_ = 0;
  glm::ivec3 size_{0};
  TexelFormat format_ = TexelFormat::R32F;
  std::string label_;
};

// Bytes per texel of a format.
std::size_t texelBytes(TexelFormat format);

}  // namespace hf::gl
