// SPDX-License-Identifier: GPL-3.0-or-later
#include "compute/texture3d.h"

#include "common/error.h"

namespace hf::compute {

Texture3D::Texture3D(const glm::ivec3& size, TexelFormat format, const std::string& label)
    : impl_(currentDevice().makeTexture(size, format, label)), size_(size), format_(format), label_(label) {}

Texture3D::~Texture3D() = default;
Texture3D::Texture3D(Texture3D&& other) noexcept = default;
Texture3D& Texture3D::operator=(Texture3D&& other) noexcept = default;

void Texture3D::download(void* dst, std::size_t bytes) const {
  if (bytes != texels() * bytesPerTexel()) throw Error("download of '" + label_ + "': wrong buffer size");
  impl_->download(dst, bytes);
}

void Texture3D::upload(const void* src, std::size_t bytes) {
  if (bytes != texels() * bytesPerTexel()) throw Error("upload to '" + label_ + "': wrong buffer size");
  impl_->upload(src, bytes);
}

}  // namespace hf::compute
