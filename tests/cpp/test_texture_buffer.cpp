// SPDX-License-Identifier: GPL-3.0-or-later
// Texture3D and StorageBuffer: exact round trips for every texel format, the x-fastest layout
// the shaders see, zero-initialisation and clear(), and the errors for misuse.
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "common/error.h"
#include "compute/compute_program.h"
#include "compute/storage_buffer.h"
#include "compute/texture3d.h"
#include "gl/gl_program.h"
#include "test_util.h"

namespace hf::gl {
using namespace hf::compute;  // the device interface these GL tests exercise
namespace {

using hf::test::contains;

// Odd, non-cubic extents so row alignment and axis order both matter.
constexpr glm::ivec3 kSize(5, 7, 3);
constexpr std::size_t kTexels = 5 * 7 * 3;

class TextureBufferTest : public hf::test::DeviceTest {};

// Distinct float values, including ones a lossy path would not keep.
std::vector<float> floatPattern(std::size_t n) {
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<float>(i) * 0.37f - 11.0f + 1.0e-7f * static_cast<float>(i);
  v[0] = std::numeric_limits<float>::denorm_min() * 3.0f;
  v[1] = -0.0f;
  v[2] = 3.4e38f;
  v[3] = -1.0e-30f;
  return v;
}

TEST_F(TextureBufferTest, R32FRoundTripIsBitExact) {
  const std::vector<float> in = floatPattern(kTexels);
  const std::vector<float> out = onGl([&] {
    Texture3D t(kSize, TexelFormat::R32F, "r32f");
    EXPECT_EQ(t.bytesPerTexel(), 4u);
    EXPECT_EQ(t.texels(), kTexels);
    t.upload(in.data(), in.size() * sizeof(float));
    std::vector<float> o(kTexels, 99.0f);
    t.download(o.data(), o.size() * sizeof(float));
    return o;
  });
  ASSERT_EQ(out.size(), in.size());
  EXPECT_EQ(std::memcmp(out.data(), in.data(), in.size() * sizeof(float)), 0);
}

TEST_F(TextureBufferTest, RGBA32FRoundTripIsBitExact) {
  const std::vector<float> in = floatPattern(kTexels * 4);
  const std::vector<float> out = onGl([&] {
    Texture3D t(kSize, TexelFormat::RGBA32F, "rgba32f");
    EXPECT_EQ(t.bytesPerTexel(), 16u);
    t.upload(in.data(), in.size() * sizeof(float));
    std::vector<float> o(kTexels * 4, 99.0f);
    t.download(o.data(), o.size() * sizeof(float));
    return o;
  });
  EXPECT_EQ(std::memcmp(out.data(), in.data(), in.size() * sizeof(float)), 0);
}

TEST_F(TextureBufferTest, R8UIRoundTripWithOddRowLength) {
  std::vector<std::uint8_t> in(kTexels);
  for (std::size_t i = 0; i < kTexels; ++i) in[i] = static_cast<std::uint8_t>((i * 37u + 11u) & 0xffu);
  in[0] = 255;
  const std::vector<std::uint8_t> out = onGl([&] {
    Texture3D t(kSize, TexelFormat::R8UI, "r8ui");
    EXPECT_EQ(t.bytesPerTexel(), 1u);
    t.upload(in.data(), in.size());
    std::vector<std::uint8_t> o(kTexels, 0xAB);
    t.download(o.data(), o.size());
    return o;
  });
  EXPECT_EQ(out, in);
}

TEST_F(TextureBufferTest, NewTextureIsZeroAndClearZeroes) {
  const auto [fresh, cleared] = onGl([] {
    Texture3D t(kSize, TexelFormat::RGBA32F, "zero");
    std::vector<float> a(kTexels * 4, 7.0f);
    t.download(a.data(), a.size() * sizeof(float));
    std::vector<float> ones(kTexels * 4, 1.0f);
    t.upload(ones.data(), ones.size() * sizeof(float));
    t.clear();
    std::vector<float> b(kTexels * 4, 7.0f);
    t.download(b.data(), b.size() * sizeof(float));
    return std::make_pair(a, b);
  });
  EXPECT_EQ(fresh, std::vector<float>(kTexels * 4, 0.0f));
  EXPECT_EQ(cleared, std::vector<float>(kTexels * 4, 0.0f));
}

// The documented layout (index = i + nx*(j + ny*k)) is the one imageLoad sees in shaders.
class TextureBufferGlTest : public hf::test::GlOnlyTest {};

TEST_F(TextureBufferGlTest, UploadLayoutIsXFastestAsShadersSeeIt) {
  const char* src = R"(
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(r32f, binding = 0) readonly uniform image3D u_f;
layout(r8ui, binding = 1) readonly uniform uimage3D u_u;
layout(std430, binding = 0) writeonly buffer Out { vec2 o[]; };
uniform ivec3 u_size;
void main() {
  ivec3 c = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(c, u_size))) return;
  int n = c.x + u_size.x * (c.y + u_size.y * c.z);
  o[n] = vec2(imageLoad(u_f, c).x, float(imageLoad(u_u, c).x));
}
)";
  std::vector<float> f(kTexels);
  std::vector<std::uint8_t> u(kTexels);
  for (std::size_t n = 0; n < kTexels; ++n) {
    f[n] = static_cast<float>(n) + 0.5f;
    u[n] = static_cast<std::uint8_t>(200 - n);
  }
  const std::vector<float> seen = onGl([&] {
    Texture3D tf(kSize, TexelFormat::R32F, "f");
    Texture3D tu(kSize, TexelFormat::R8UI, "u");
    tf.upload(f.data(), f.size() * sizeof(float));
    tu.upload(u.data(), u.size());
    StorageBuffer out(kTexels * 2 * sizeof(float), "fetched");
    GlProgram p("fetch.comp", src, {});
    tf.bindImage(0, Access::Read);
    tu.bindImage(1, Access::Read);
    out.bind(0);
    p.setIVec3("u_size", kSize);
    p.dispatch(kSize);
    std::vector<float> o(kTexels * 2);
    out.download(o.data(), o.size() * sizeof(float));
    return o;
  });
  for (std::size_t n = 0; n < kTexels; ++n) {
    EXPECT_EQ(seen[2 * n], f[n]) << "texel " << n;
    EXPECT_EQ(seen[2 * n + 1], static_cast<float>(u[n])) << "texel " << n;
  }
}

TEST_F(TextureBufferTest, WrongBufferSizeThrowsAndLeavesTheTextureAlone) {
  const std::vector<float> in = floatPattern(kTexels);
  onGl([&] {
    Texture3D t(kSize, TexelFormat::R32F, "sized");
    t.upload(in.data(), in.size() * sizeof(float));
    std::vector<float> big(kTexels + 1, 5.0f);
    EXPECT_THROW(t.upload(big.data(), (kTexels - 1) * sizeof(float)), Error);
    EXPECT_THROW(t.upload(big.data(), (kTexels + 1) * sizeof(float)), Error);
    EXPECT_THROW(t.download(big.data(), (kTexels + 1) * sizeof(float)), Error);
    try {
      t.download(big.data(), kTexels);  // bytes, not texels
      ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
      EXPECT_TRUE(contains(e.what(), "'sized'")) << e.what();
      EXPECT_TRUE(contains(e.what(), "wrong buffer size")) << e.what();
    }
    std::vector<float> out(kTexels);
    t.download(out.data(), out.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(out.data(), in.data(), in.size() * sizeof(float)), 0);
    // An RGBA texture wants 16 bytes per texel: the R32F size is wrong for it.
    Texture3D rgba(kSize, TexelFormat::RGBA32F, "rgba");
    EXPECT_THROW(rgba.upload(in.data(), in.size() * sizeof(float)), Error);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  });
}

TEST_F(TextureBufferTest, ImpossibleSizeThrowsGlErrorNamingTheTexture) {
  onGl([] {
    for (const glm::ivec3 bad : {glm::ivec3(0, 4, 4), glm::ivec3(1 << 20, 1, 1)}) {
      try {
        Texture3D t(bad, TexelFormat::R32F, "impossible");
        ADD_FAILURE() << "texture of " << bad.x << "x" << bad.y << "x" << bad.z << " was made";
      } catch (const GlError& e) {
        EXPECT_TRUE(contains(e.what(), "'impossible'")) << e.what();
      }
    }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));  // drained by the check
    Texture3D ok(glm::ivec3(2), TexelFormat::R32F, "fine afterwards");
    float v[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    ok.upload(v, sizeof v);
  });
}

TEST_F(TextureBufferTest, MoveKeepsTheDataAndEmptiesTheSource) {
  const std::vector<float> in = floatPattern(kTexels);
  onGl([&] {
    Texture3D a(kSize, TexelFormat::R32F, "moved");
    a.upload(in.data(), in.size() * sizeof(float));
    Texture3D b(std::move(a));
    EXPECT_EQ(b.size(), kSize);
    EXPECT_EQ(b.label(), "moved");
    std::vector<float> out(kTexels);
    b.download(out.data(), out.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(out.data(), in.data(), in.size() * sizeof(float)), 0);
    Texture3D c(glm::ivec3(2), TexelFormat::R8UI, "target");
    c = std::move(b);
    EXPECT_EQ(c.size(), kSize);
    EXPECT_EQ(c.format(), TexelFormat::R32F);
    std::fill(out.begin(), out.end(), 0.0f);
    c.download(out.data(), out.size() * sizeof(float));
    EXPECT_EQ(std::memcmp(out.data(), in.data(), in.size() * sizeof(float)), 0);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  });  // a and b (moved from) and c die here: only c deletes a texture
}

TEST_F(TextureBufferTest, StorageBufferRoundTripWithOffsets) {
  onGl([] {
    constexpr std::size_t kBytes = 1000;  // not a multiple of 16
    StorageBuffer b(kBytes, "ssbo");
    EXPECT_EQ(b.bytes(), kBytes);
    std::vector<std::uint8_t> zero(kBytes, 0xCD);
    b.download(zero.data(), kBytes);
    b.clear();
    b.download(zero.data(), kBytes);
    EXPECT_EQ(zero, std::vector<std::uint8_t>(kBytes, 0));

    std::vector<std::uint8_t> all(kBytes);
    for (std::size_t i = 0; i < kBytes; ++i) all[i] = static_cast<std::uint8_t>(i * 7 + 3);
    b.upload(all.data(), kBytes);
    const std::uint8_t patch[5] = {1, 2, 3, 4, 5};
    b.upload(patch, sizeof patch, 995);  // ends exactly at the end
    b.upload(patch, sizeof patch, 13);
    std::copy(patch, patch + 5, all.begin() + 995);
    std::copy(patch, patch + 5, all.begin() + 13);
    std::vector<std::uint8_t> whole(kBytes);
    b.download(whole.data(), kBytes);
    EXPECT_EQ(whole, all);
    std::uint8_t part[7] = {};
    b.download(part, sizeof part, 11);
    EXPECT_EQ(std::vector<std::uint8_t>(part, part + 7), std::vector<std::uint8_t>(all.begin() + 11, all.begin() + 18));

    EXPECT_THROW(b.upload(patch, sizeof patch, 996), Error);
    EXPECT_THROW(b.download(part, 1, kBytes), Error);
    EXPECT_THROW(b.download(whole.data(), kBytes + 1), Error);
    try {
      b.upload(patch, sizeof patch, kBytes);
      ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
      EXPECT_TRUE(contains(e.what(), "'ssbo'")) << e.what();
    }
    // Nothing past the end was written by the refused calls.
    b.download(whole.data(), kBytes);
    EXPECT_EQ(whole, all);
  });
}

TEST_F(TextureBufferTest, ZeroByteStorageBufferThrowsGlError) {
  onGl([] {
    EXPECT_THROW(StorageBuffer(0, "empty"), GlError);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  });
}

TEST(TexelBytes, PerFormat) {
  EXPECT_EQ(texelBytes(TexelFormat::R32F), 4u);
  EXPECT_EQ(texelBytes(TexelFormat::RGBA32F), 16u);
  EXPECT_EQ(texelBytes(TexelFormat::R8UI), 1u);
}

}  // namespace
}  // namespace hf::gl
