// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Writes one simulation frame as an OpenVDB file (the cache format Blender, Houdini and
// Mantaflow read). This layer knows dense arrays, grids and files only, never the solver: the
// caller hands it plain float arrays (x fastest) and the grid's placement. OpenVDB's headers
// stay inside vdb_writer.cpp (they are slow to compile), so this header is cheap to include.
//
// What a file holds (one per frame):
//   density   FloatGrid, class fog volume: cell-centred concentration.
//   velocity  Vec3SGrid (optional), class unknown, vector type invariant: the MAC face
//             velocities averaged to cell centres (m/s, world axes), so it shares density's
//             voxels and transform. Not staggered (Mantaflow writes a staggered grid; Blender
//             and most readers only sample it, for which centred values are what they expect).
//   pressure  FloatGrid (optional), class unknown: cell-centred pressure (Pa) as given.
// Transform: linear, voxel size = the cell edge h; OpenVDB voxel (i, j, k) has its centre at
// index (i, j, k), so the translation is origin + h/2 and cell centres land exactly where the
// simulation has them; the active bounding box is the domain (or less, see tolerance).
// Sparse: a voxel whose |value| (|vector| for velocity) <= tolerance stays inactive
// (background 0). Metadata go on the file and on every grid.
// The file is written under a temporary name in the same folder and renamed when complete,
// so a crash or kill never leaves a partial file under the final name.
#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "common/error.h"

namespace hf::io {

// A file could not be written or read as OpenVDB (disk, permissions, format).
class VdbError : public Error {
 public:
  using Error::Error;
};

enum class Compression { None, Zip, Blosc };

using MetaValue = std::variant<bool, std::int64_t, double, std::string, glm::vec3, glm::ivec3>;
using Metadata = std::vector<std::pair<std::string, MetaValue>>;

// A dense array of `shape` floats, x fastest (index = i + nx*(j + ny*k)); not owned.
struct DenseView {
  const float* data = nullptr;
  glm::ivec3 shape{0};
};

struct VdbFrame {
  glm::ivec3 resolution{0};            // cells per axis
  float voxel_size_m = 0.0f;           // cell edge h, m
  glm::vec3 origin_m{0.0f};            // world position of the domain's minimum corner, m
  DenseView density;                   // required, shape = resolution
  // Optional MAC velocity: u (nx+1, ny, nz), v (nx, ny+1, nz), w (nx, ny, nz+1), m/s.
  std::array<DenseView, 3> velocity{};
  DenseView pressure;                  // optional, shape = resolution, Pa
  Metadata metadata;
};

struct VdbWriteOptions {
  Compression compression = Compression::Blosc;
  bool half_float = false;             // store float grids as 16-bit halves (lossy, ~half the size)
  float tolerance = 0.0f;              // |value| <= tolerance -> inactive voxel (>= 0)
};

// Throws InvalidArgument for shapes or values it cannot write (message says which) and
// VdbError when the file cannot be written; no file appears under `path` in either case.
void writeVdbFrame(const std::string& path, const VdbFrame& frame, const VdbWriteOptions& options);

// Names of the compressions this OpenVDB build supports ("none", "zip", "blosc").
std::vector<std::string> supportedCompressions();
// The OpenVDB library version, e.g. "10.0.1".
std::string openvdbVersion();

}  // namespace hf::io
