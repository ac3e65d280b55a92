// SPDX-License-Identifier: GPL-3.0-or-later
// In the obstacle test binary: it needs the mesh probe (the highest layer it includes).
// GL limits the engine relies on that no error would show on llvmpipe: image units per program
// (GL guarantees 8) and the shader storage block size (GL guarantees 128 MiB).
#include <GL/gl.h>
#include <GL/glext.h>
#include <gtest/gtest.h>

#include <string>

#include "common/error.h"
#include "fluid/grid.h"
#include "compute/compute_program.h"
#include "gl/gl_program.h"
#include "compute/storage_buffer.h"
#include "compute/workgroup.h"
#include "obstacle/mesh_probe.h"
#include "test_util.h"

namespace hf::gl {
namespace {
using namespace hf::compute;

using hf::test::contains;

class GlLimits : public hf::test::GlOnlyTest {};

// A stage with `n` image uniforms on units 0..n-1, every one used.
std::string imagesStage(int n) {
  std::string s = "layout(local_size_x = 1) in;\n";
  for (int i = 0; i < n; ++i) {
    s += "layout(r32f, binding = " + std::to_string(i) + ") uniform image3D u_img" + std::to_string(i) + ";\n";
  }
  s += "void main() {\n  float v = 0.0;\n";
  for (int i = 0; i < n; ++i) s += "  v += imageLoad(u_img" + std::to_string(i) + ", ivec3(0)).r;\n";
  s += "  imageStore(u_img0, ivec3(0), vec4(v));\n}\n";
  return s;
}

TEST_F(GlLimits, ImageUnitsAreCountedAndANinthIsRefused) {
  onGl([] {
    GlProgram eight("eight.comp", imagesStage(8), {});
    EXPECT_EQ(eight.imageUnits(), 8);
    try {
      GlProgram nine("nine.comp", imagesStage(9), {});
      ADD_FAILURE() << "a program with 9 image units was accepted";
    } catch (const GlError& e) {
      EXPECT_TRUE(contains(e.what(), "nine.comp uses 9 image units")) << e.what();
      EXPECT_TRUE(contains(e.what(), "guarantees only 8")) << e.what();
    }
  });
}

TEST_F(GlLimits, TheFullestStagesStayWithinTheGuaranteedEight) {
  onGl([] {
    Defines pair = cellGroupDefines();
    pair.emplace_back("FIELD_AT", "3");
    pair.emplace_back("PAIR", "1");
    EXPECT_EQ(GlProgram("advect.comp", pair).imageUnits(), 8);  // 3 velocity, mask, 2 in, 2 out
    Defines face = cellGroupDefines();
    face.emplace_back("FIELD_AT", "0");
    EXPECT_EQ(GlProgram("advect.comp", face).imageUnits(), 6);
    EXPECT_EQ(GlProgram("maccormack.comp", cellGroupDefines()).imageUnits(), 8);
  });
}

TEST_F(GlLimits, StorageBufferPastTheBlockLimitIsRefusedBeforeAllocation) {
  onGl([] {
    const std::size_t limit = maxStorageBlockBytes();
    ASSERT_GE(limit, std::size_t{128} << 20);  // the GL 4.3 minimum
    try {
      StorageBuffer too_big(limit + 4, "test block");
      ADD_FAILURE() << "a buffer past GL_MAX_SHADER_STORAGE_BLOCK_SIZE was allocated";
    } catch (const GlError& e) {
      EXPECT_TRUE(contains(e.what(), "'test block'")) << e.what();
      EXPECT_TRUE(contains(e.what(), "GL_MAX_SHADER_STORAGE_BLOCK_SIZE) is " + std::to_string(limit >> 20) + " MiB"))
          << e.what();
    }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
  });
}

TEST_F(GlLimits, MeshProbeOnAGridPastTheBlockLimitNamesTheGrid) {
  onGl([] {
    const std::size_t limit = maxStorageBlockBytes();
    // The smallest cube whose crossings buffer (4 bytes per cell) exceeds the limit.
    int n = 1;
    while (std::size_t{4} * n * n * n <= limit) ++n;
    fluid::Grid g;
    g.res = glm::ivec3(n);
    g.cell_size_m = 1.0f / static_cast<float>(n);
    const std::string name = std::to_string(n) + "x" + std::to_string(n) + "x" + std::to_string(n) + " grid";
    try {
      obstacle::MeshProbe probe(g);
      ADD_FAILURE() << "a mesh probe on " << name << " was built";
    } catch (const GlError& e) {
      EXPECT_TRUE(contains(e.what(), "mesh crossings of the " + name)) << e.what();
    }
  });
}

}  // namespace
}  // namespace hf::gl
