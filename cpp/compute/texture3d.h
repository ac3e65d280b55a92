// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// One 3D texture of the current device (RAII): a GL texture or a CPU array, x fastest.
#include <cstddef>
#include <memory>
#include <string>

#include <glm/glm.hpp>

#include "compute/device.h"

namespace hf::compute {

class Texture3D {
 public:
  // Every texel starts at zero.
  Texture3D(const glm::ivec3& size, TexelFormat format, const std::string& label);
  ~Texture3D();
  Texture3D(Texture3D&& other) noexcept;
  Texture3D& operator=(Texture3D&& other) noexcept;
  Texture3D(const Texture3D&) = delete;
  Texture3D& operator=(const Texture3D&) = delete;

  glm::ivec3 size() const { return size_; }
  std::size_t texels() const { return static_cast<std::size_t>(size_.x) * size_.y * size_.z; }
  std::size_t bytesPerTexel() const { return texelBytes(format_); }
  TexelFormat format() const { return format_; }
  const std::string& label() const { return label_; }

  // Binds the texture to image `unit` for the programs dispatched next.
  void bindImage(unsigned unit, Access access) const { impl_->bindImage(unit, access); }
  void clear() { impl_->clear(); }  // every texel to zero
  // Copies the whole texture into dst (texels() * bytesPerTexel() bytes), x fastest.
  void download(void* dst, std::size_t bytes) const;
  void upload(const void* src, std::size_t bytes);
  // The caller's word that since its last such call (or since the texture was made) the programs
  // it dispatched wrote only texels in [origin, origin + extent) (an empty extent: none), so that a
  // device may update what it derived from the texture there only (the CPU's regular rows,
  // cpu/regular_rows.h). A clear or an upload in between voids the word: all is derived anew.
  void changedOnlyIn(const glm::ivec3& origin, const glm::ivec3& extent) { impl_->changedOnlyIn(origin, extent); }

 private:
  std::unique_ptr<TextureImpl> impl_;
  glm::ivec3 size_{0};
  TexelFormat format_ = TexelFormat::R32F;
  std::string label_;
};

}  // namespace hf::compute
