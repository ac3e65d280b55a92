// SPDX-License-Identifier: GPL-3.0-or-later
// The CPU backend's row flags (cpu/regular_rows.h): a row is open inside only where its cells
// 1 .. nx - 2 all have six links and six unit fractions, and its first or last cell takes the wall
// links as constants only where its mask is exactly those and its five linked faces are whole (the
// stages then read neither its mask nor its fractions, so a wrong flag would change the result).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "cpu/regular_rows.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {
namespace {

class RegularRowsFlags : public ::testing::Test {
 protected:
  static constexpr int kX = 9, kY = 5, kZ = 4;

  void SetUp() override {
    masks.assign(static_cast<std::size_t>(kX * kY * kZ), static_cast<std::uint8_t>(kAllLinks));
    for (int z = 0; z < kZ; ++z) {
      for (int y = 0; y < kY; ++y) {
        masks[static_cast<std::size_t>(cell(0, y, z))] = static_cast<std::uint8_t>(kWallLowLinks);
        masks[static_cast<std::size_t>(cell(kX - 1, y, z))] = static_cast<std::uint8_t>(kWallHighLinks);
      }
    }
    plane = static_cast<std::size_t>((kX + 1) * (kY + 1) * (kZ + 1));
    faces.assign(4 * plane, 1.0f);
  }

  static int cell(int x, int y, int z) { return x + kX * (y + kY * z); }
  static int face(int x, int y, int z) { return x + (kX + 1) * (y + (kY + 1) * z); }
  float& fx(int x, int y, int z) { return faces[static_cast<std::size_t>(face(x, y, z))]; }
  float& fy(int x, int y, int z) { return faces[plane + static_cast<std::size_t>(face(x, y, z))]; }
  float& fz(int x, int y, int z) { return faces[2 * plane + static_cast<std::size_t>(face(x, y, z))]; }
  std::uint8_t& mask(int x, int y, int z) { return masks[static_cast<std::size_t>(cell(x, y, z))]; }

  // The masks and the faces as bound images at a version.
  ImageBinding maskImage(std::uint64_t at) {
    ImageBinding m;
    m.data = masks.data();
    m.size = glm::ivec3(kX, kY, kZ);
    m.format = ImageFormat::R8UI;
    m.version = at;
    return m;
  }
  ImageBinding faceImage(std::uint64_t at) {
    ImageBinding f;
    f.data = faces.data();
    f.size = glm::ivec3(kX + 1, kY + 1, kZ + 1);
    f.plane = plane;
    f.format = ImageFormat::RGBA32F;
    f.version = at;
    return f;
  }

  // The flags `rows` gives for the images m and f.
  static std::vector<std::uint8_t> flagsOf(RegularRows& rows, const ImageBinding& m, const ImageBinding& f, bool x86_v3) {
    ThreadPool pool(2);
    const std::uint8_t* out = rows.flags(m, f, glm::ivec3(kX, kY, kZ), pool, x86_v3 && cpuHasX86V3());
    return std::vector<std::uint8_t>(out, out + kY * kZ);
  }

  std::vector<std::uint8_t> flags(bool x86_v3) {
    RegularRows rows;
    const ImageBinding m = maskImage(++version);
    return flagsOf(rows, m, faceImage(++version), x86_v3);
  }

  std::vector<std::uint8_t> masks;
  std::vector<float> faces;
  std::size_t plane = 0;
  std::uint64_t version = 0;
};

TEST_F(RegularRowsFlags, EachRowsEndsAgainstAWallOnlyWhereTheirMaskAndLinkedFacesSaySo) {
  const std::uint8_t all = kOpenInside | kWallLow | kWallHigh;
  std::vector<std::uint8_t> want(kY * kZ, all);
  auto row = [&](int y, int z) -> std::uint8_t& { return want[static_cast<std::size_t>(y + kY * z)]; };
  fy(0, 2, 1) = 0.5f;  // cut between (0, 1, 1) and (0, 2, 1): the +y face of one row's first cell, the -y of the next's
  row(1, 1) &= static_cast<std::uint8_t>(~kWallLow);
  row(2, 1) &= static_cast<std::uint8_t>(~kWallLow);
  fz(kX - 1, 3, 2) = 0.0f;  // the last cell's -z face of row (3, 2) (the +z face of row (3, 1))
  row(3, 2) &= static_cast<std::uint8_t>(~kWallHigh);
  row(3, 1) &= static_cast<std::uint8_t>(~kWallHigh);
  mask(0, 1, 3) = static_cast<std::uint8_t>(kAllLinks);  // linked past the wall: not the constant
  row(1, 3) &= static_cast<std::uint8_t>(~kWallLow);
  mask(kX - 1, 4, 3) = static_cast<std::uint8_t>(kWallHighLinks | 64u);  // an open top as well
  row(4, 3) &= static_cast<std::uint8_t>(~kWallHigh);
  fx(0, 2, 2) = 0.25f;  // the first cell's unlinked -x face: read by no stage, so the flag stays
  mask(4, 0, 2) = static_cast<std::uint8_t>(kWallLowLinks);  // an inner cell closed on -x
  row(0, 2) &= static_cast<std::uint8_t>(~kOpenInside);
  fx(1, 4, 0) = 0.75f;  // the face between cells 0 and 1: cell 0's linked +x and cell 1's -x
  row(4, 0) &= static_cast<std::uint8_t>(~(kWallLow | kOpenInside));
  for (bool v3 : {false, true}) {
    const std::vector<std::uint8_t> got = flags(v3);
    for (int z = 0; z < kZ; ++z) {
      for (int y = 0; y < kY; ++y) {
        EXPECT_EQ(int(got[static_cast<std::size_t>(y + kY * z)]), int(row(y, z))) << "row y " << y << ", z " << z << (v3 ? ", AVX2" : "");
      }
    }
  }
}

// The flags kept across changes: where both textures' words (ImageBinding::change) cover the
// change since the flags were derived, only the rows the words' texels touch are derived again
// (a face texel also touches the row below and the one behind); else the whole grid is.
TEST_F(RegularRowsFlags, AWordOnWhereTheTexturesChangedRederivesOnlyThoseRows) {
  RegularRows rows;
  ImageBinding m = maskImage(1);
  ImageBinding f = faceImage(2);
  auto get = [&](RegularRows& r) { return flagsOf(r, m, f, true); };
  const std::uint8_t all = kOpenInside | kWallLow | kWallHigh;
  EXPECT_EQ(get(rows), std::vector<std::uint8_t>(kY * kZ, all));

  // A cut y face at texel (3, 2, 1) (rows (1, 1) and (2, 1)), a closed inner cell in row (3, 3),
  // each with its word; and a change outside both words (row (0, 0)), which they do not cover.
  fy(3, 2, 1) = 0.5f;
  mask(5, 3, 3) = static_cast<std::uint8_t>(kWallLowLinks);
  mask(2, 0, 0) = 0;
  const ChangeNote mask_word{1, 3, glm::ivec3(5, 3, 3), glm::ivec3(1)};
  const ChangeNote face_word{2, 4, glm::ivec3(3, 2, 1), glm::ivec3(1)};
  m.version = 3;
  m.change = &mask_word;
  f.version = 4;
  f.change = &face_word;
  std::vector<std::uint8_t> want(kY * kZ, all);
  want[1 + kY * 1] = kWallLow | kWallHigh;
  want[2 + kY * 1] = kWallLow | kWallHigh;
  want[3 + kY * 3] = kWallLow | kWallHigh;
  EXPECT_EQ(get(rows), want) << "the rows the words touch, and only those, derived again";

  // A word from another version than the flags' (a clear, an upload or a write unsaid between):
  // everything derived again, row (0, 0) too.
  const ChangeNote stale_word{2, 5, glm::ivec3(5, 3, 3), glm::ivec3(1)};
  m.version = 5;
  m.change = &stale_word;
  want[0] = kWallLow | kWallHigh;
  EXPECT_EQ(get(rows), want);
  RegularRows fresh;
  EXPECT_EQ(get(fresh), want) << "the same flags as derived from nothing";
}

TEST(RegularRowsWallLinks, OnlyTheFlaggedEndTakesAConstant) {
  EXPECT_EQ(wallLinks(kWallLow | kWallHigh, 0, 9), kWallLowLinks);
  EXPECT_EQ(wallLinks(kWallLow | kWallHigh, 8, 9), kWallHighLinks);
  EXPECT_EQ(wallLinks(kWallHigh, 0, 9), 0u);
  EXPECT_EQ(wallLinks(kWallLow, 8, 9), 0u);
  EXPECT_EQ(wallLinks(kWallLow | kWallHigh, 4, 9), 0u);
}

}  // namespace
}  // namespace hf::cpu
