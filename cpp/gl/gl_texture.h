// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// compute::Texture3D on GL: one immutable-storage 3D texture (RAII), zeroed when made. Float
// textures sample with trilinear filtering and clamp-to-edge; integer ones are fetched exactly.
#include <string>

#include <glm/glm.hpp>

#include "compute/device.h"

namespace hf::gl {

class GlTexture final : public compute::TextureImpl {
 public:
  GlTexture(const glm::ivec3& size, compute::TexelFormat format, const std::string& label);
  ~GlTexture() override;
  GlTexture(const GlTexture&) = delete;
  GlTexture& operator=(const GlTexture&) = delete;

  void bindImage(unsigned unit, compute::Access access) const override;
  void clear() override;
  void download(void* dst, std::size_t bytes) const override;
  void upload(const void* src, std::size_t bytes) override;

 private:
  unsigned int id_ = 0;
  glm::ivec3 size_{0};
  compute::TexelFormat format_;
  std::string label_;
};

}  // namespace hf::gl
