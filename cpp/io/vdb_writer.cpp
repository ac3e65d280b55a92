// SPDX-License-Identifier: GPL-3.0-or-later
// The only file that includes OpenVDB: see vdb_writer.h for what a frame file holds.
#include "io/vdb_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <boost/uuid/name_generator_sha1.hpp>
#include <boost/uuid/uuid_io.hpp>
#include <fstream>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <string>
#include <vector>
#include <zlib.h>

#include "common/bulk_allocator.h"
#include "common/format.h"

namespace hf::io {
namespace {

std::string shapeText(const glm::ivec3& s) {
  return "(" + std::to_string(s.x) + ", " + std::to_string(s.y) + ", " + std::to_string(s.z) + ")";
}

void initOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

std::size_t count(const glm::ivec3& s) { return static_cast<std::size_t>(s.x) * s.y * s.z; }

void checkView(const DenseView& v, const glm::ivec3& expected, const char* what) {
  if (v.data == nullptr) throw InvalidArgument(std::string(what) + " is missing");
  if (v.shape != expected) {
    throw InvalidArgument(std::string(what) + " must have shape " + shapeText(expected) + ", got " +
                          shapeText(v.shape));
  }
  const std::size_t n = count(expected);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v.data[i])) {
      throw InvalidArgument(std::string(what) + " holds a non-finite value at flat index " + std::to_string(i) +
                            "; only finite fields can be written");
    }
  }
}

void checkFrame(const VdbFrame& f, const VdbWriteOptions& o) {
  if (glm::any(glm::lessThan(f.resolution, glm::ivec3(1)))) {
    // The resolution is the density array's shape: say so, naming the array the caller passed.
    throw InvalidArgument("density must have at least 1 cell on every axis (the grid's resolution), got shape " +
                          shapeText(f.resolution));
  }
  if (!std::isfinite(f.voxel_size_m) || f.voxel_size_m <= 0.0f) {
    throw InvalidArgument("voxel size must be a positive finite length (m), got " + num(f.voxel_size_m));
  }
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(f.origin_m[a])) throw InvalidArgument("origin must be finite (m), got " + vecText(f.origin_m));
  }
  if (!std::isfinite(o.tolerance) || o.tolerance < 0.0f) {
    throw InvalidArgument("tolerance must be a finite value >= 0, got " + num(o.tolerance));
  }
#ifndef OPENVDB_USE_BLOSC
  if (o.compression == Compression::Blosc) throw InvalidArgument("this OpenVDB build has no blosc: use zip or none");
#endif
#ifndef OPENVDB_USE_ZLIB
  if (o.compression == Compression::Zip) throw InvalidArgument("this OpenVDB build has no zip: use blosc or none");
#endif
  checkView(f.density, f.resolution, "density");
  const bool any_velocity = f.velocity[0].data || f.velocity[1].data || f.velocity[2].data;
  if (any_velocity) {
    static const char* names[3] = {"velocity x (u on x-faces)", "velocity y (v on y-faces)", "velocity z (w on z-faces)"};
    for (int a = 0; a < 3; ++a) {
      glm::ivec3 s = f.resolution;
      s[a] += 1;
      checkView(f.velocity[a], s, names[a]);
    }
  }
  if (f.pressure.data) checkView(f.pressure, f.resolution, "pressure");
  for (const auto& [key, value] : f.metadata) {
    static_cast<void>(value);
    if (key.empty()) throw InvalidArgument("metadata names must not be empty");
    // OpenVDB keeps a grid's own properties as metadata under these names.
    if (key == "name" || key == "class" || key == "vector_type" || key == "is_local_space" ||
        key == "is_saved_as_half_float" || key == "file_bbox_min" || key == "file_bbox_max" ||
        key == "file_compression" || key == "file_mem_bytes" || key == "file_voxel_count" ||
        key == "file_delayed_load") {
      throw InvalidArgument("metadata name '" + key + "' is reserved by OpenVDB (name, class, vector_type, "
                            "is_local_space, is_saved_as_half_float, file_bbox_min/max, file_compression, "
                            "file_mem_bytes, file_voxel_count, file_delayed_load); choose another");
    }
  }
}

openvdb::math::Transform::Ptr cellTransform(const VdbFrame& f) {
  const double h = f.voxel_size_m;
  auto xf = openvdb::math::Transform::createLinearTransform(h);
  // Voxel (i, j, k)'s centre is index (i, j, k); the simulation's cell centre is origin + (i + 1/2) h.
  xf->postTranslate(openvdb::Vec3d(f.origin_m.x + 0.5 * h, f.origin_m.y + 0.5 * h, f.origin_m.z + 0.5 * h));
  return xf;
}

openvdb::CoordBBox cellBox(const glm::ivec3& r) {
  return openvdb::CoordBBox(openvdb::Coord(0, 0, 0), openvdb::Coord(r.x - 1, r.y - 1, r.z - 1));
}

openvdb::FloatGrid::Ptr floatGrid(const std::string& name, const DenseView& v, const VdbFrame& f,
                                  const VdbWriteOptions& o, openvdb::GridClass cls) {
  auto grid = openvdb::FloatGrid::create(0.0f);
  // Read only: Dense wants a mutable pointer but copyFromDense only reads it.
  openvdb::tools::Dense<float, openvdb::tools::LayoutXYZ> dense(cellBox(f.resolution), const_cast<float*>(v.data));
  openvdb::tools::copyFromDense(dense, grid->tree(), o.tolerance);
  grid->setName(name);
  grid->setGridClass(cls);
  return grid;
}

// u, v, w on faces -> the mean of each cell's two faces, at cell centres; |v| <= tolerance -> 0.
// (A BulkAllocator array: every element is written below, and a bake's frames reuse one block.)
openvdb::Vec3SGrid::Ptr velocityGrid(const VdbFrame& f, const VdbWriteOptions& o) {
  const glm::ivec3 r = f.resolution;
  std::vector<openvdb::Vec3s, BulkAllocator<openvdb::Vec3s>> centred(count(r));
  const float tol2 = o.tolerance * o.tolerance;
  std::size_t n = 0;
  for (int k = 0; k < r.z; ++k) {
    for (int j = 0; j < r.y; ++j) {
      for (int i = 0; i < r.x; ++i, ++n) {
        const float* u = f.velocity[0].data;
        const float* v = f.velocity[1].data;
        const float* w = f.velocity[2].data;
        const std::size_t iu = static_cast<std::size_t>(i) + (r.x + 1) * (j + static_cast<std::size_t>(r.y) * k);
        const std::size_t iv = static_cast<std::size_t>(i) + r.x * (j + static_cast<std::size_t>(r.y + 1) * k);
        const std::size_t iw = static_cast<std::size_t>(i) + r.x * (j + static_cast<std::size_t>(r.y) * k);
        const std::size_t step_w = static_cast<std::size_t>(r.x) * r.y;
        openvdb::Vec3s c(0.5f * (u[iu] + u[iu + 1]), 0.5f * (v[iv] + v[iv + r.x]), 0.5f * (w[iw] + w[iw + step_w]));
        if (c.lengthSqr() <= tol2) c = openvdb::Vec3s(0.0f);
        centred[n] = c;
      }
    }
  }
  auto grid = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.0f));
  openvdb::tools::Dense<openvdb::Vec3s, openvdb::tools::LayoutXYZ> dense(cellBox(r), centred.data());
  openvdb::tools::copyFromDense(dense, grid->tree(), openvdb::Vec3s(0.0f));
  grid->setName("velocity");
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->setVectorType(openvdb::VEC_INVARIANT);
  return grid;
}

void addMetadata(openvdb::MetaMap& map, const Metadata& meta) {
  for (const auto& [key, value] : meta) {
    std::visit(
        [&, &k = key](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, bool>) {
            map.insertMeta(k, openvdb::BoolMetadata(v));
          } else if constexpr (std::is_same_v<T, std::int64_t>) {
            map.insertMeta(k, openvdb::Int64Metadata(v));
          } else if constexpr (std::is_same_v<T, double>) {
            map.insertMeta(k, openvdb::DoubleMetadata(v));
          } else if constexpr (std::is_same_v<T, std::string>) {
            map.insertMeta(k, openvdb::StringMetadata(v));
          } else if constexpr (std::is_same_v<T, glm::vec3>) {
            map.insertMeta(k, openvdb::Vec3SMetadata(openvdb::Vec3s(v.x, v.y, v.z)));
          } else {
            map.insertMeta(k, openvdb::Vec3IMetadata(openvdb::Vec3i(v.x, v.y, v.z)));
          }
        },
        value);
  }
}

uint32_t compressionFlags(Compression c) {
  switch (c) {
    case Compression::None: return openvdb::io::COMPRESS_NONE;
    case Compression::Zip: return openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK;
    case Compression::Blosc: return openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK;
  }
  return openvdb::io::COMPRESS_NONE;
}

std::string folderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

std::string fileOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string errnoText(int err) { return std::strerror(err); }

// Flushes a written file (or folder) to the disk so a power cut cannot leave a renamed but empty file.
void syncPath(const std::string& path, bool folder) {
  const int fd = ::open(path.c_str(), folder ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) {
    if (folder) return;  // some file systems do not let folders be opened: best effort
    throw VdbError("cannot reopen '" + path + "' to flush it: " + errnoText(errno));
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && !folder) throw VdbError("cannot flush '" + path + "' to disk: " + errnoText(err));
}

// OpenVDB's header (io::Archive::writeHeader, file format 222 and later): the magic number
// (int64), the file format version and the library's major and minor versions (uint32 each), a
// grid-offsets flag (char), then a UUID as 36 characters, drawn at random for every write.
constexpr std::streamoff kUuidOffset = 8 + 4 + 4 + 4 + 1;
constexpr std::size_t kUuidChars = 36;

bool looksLikeUuid(const std::string& s) {
  if (s.size() != kUuidChars) return false;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? s[i] != '-' : !std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return true;
}

// The name a file's UUID is derived from: its size (8 bytes, little-endian) and the CRC-32 of
// each kCrcBlock bytes of it, in order (4 bytes each). Any change to the bytes changes the CRC of
// a block it falls in (but for a chance of 2^-32 per changed block), so the name tells files apart
// as well as their bytes would, at zlib's CRC-32 speed: SHA-1 (boost's) over all the bytes took
// 20 ms of the writer thread's CPU a frame of the 100x100x70 grid (3.9 MB), this about 3.
constexpr std::size_t kCrcBlock = std::size_t{1} << 16;

std::vector<unsigned char> contentName(const std::string& bytes) {
  std::vector<unsigned char> name;
  const std::uint64_t size = bytes.size();
  for (int i = 0; i < 8; ++i) name.push_back(static_cast<unsigned char>(size >> (8 * i)));
  for (std::size_t at = 0; at < bytes.size(); at += kCrcBlock) {
    const std::size_t n = std::min(kCrcBlock, bytes.size() - at);
    const uLong crc = crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data() + at), static_cast<uInt>(n));
    for (int i = 0; i < 4; ++i) name.push_back(static_cast<unsigned char>(crc >> (8 * i)));
  }
  return name;
}

// The file's random UUID replaced by one derived from its content (a name-based UUID: SHA-1 of
// contentName() of the file's bytes with the UUID's own characters as '0'), so the same frame
// baked twice (a resumed bake, a farm chunk) is the same file to the byte. A header of another
// layout is left as it was.
void deriveFileUuid(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in.tellg();
  std::string bytes(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)), '\0');
  in.seekg(0);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!in || size < 0) throw VdbError("cannot read '" + path + "' back to set its UUID");
  in.close();
  const auto at = static_cast<std::size_t>(kUuidOffset);
  if (bytes.size() < at + kUuidChars) return;
  std::int64_t magic = 0;
  std::uint32_t format = 0;
  std::memcpy(&magic, bytes.data(), sizeof magic);
  std::memcpy(&format, bytes.data() + 8, sizeof format);
  if (magic != static_cast<std::int64_t>(openvdb::OPENVDB_MAGIC) || format < 222 ||
      !looksLikeUuid(bytes.substr(at, kUuidChars))) {
    return;
  }
  bytes.replace(at, kUuidChars, kUuidChars, '0');
  const std::vector<unsigned char> content = contentName(bytes);
  boost::uuids::name_generator_sha1 name(boost::uuids::ns::oid());
  const std::string uuid = boost::uuids::to_string(name(content.data(), content.size()));
  std::fstream out(path, std::ios::binary | std::ios::in | std::ios::out);
  out.seekp(kUuidOffset);
  out.write(uuid.data(), static_cast<std::streamsize>(uuid.size()));
  out.close();
  if (!out) throw VdbError("cannot write the UUID into '" + path + "'");
}

}  // namespace

void writeVdbFrame(const std::string& path, const VdbFrame& frame, const VdbWriteOptions& options) {
  if (path.empty() || path.back() == '/') throw InvalidArgument("the VDB path must name a file, got '" + path + "'");
  checkFrame(frame, options);
  initOpenVdb();
  const std::string folder = folderOf(path);
  if (::access(folder.c_str(), W_OK) != 0) {
    throw VdbError("cannot write into folder '" + folder + "': " + errnoText(errno));
  }
  // A unique temporary name beside the target (same file system, so the rename is atomic).
  static std::atomic<unsigned> serial{0};
  const std::string tmp = folder + "/." + fileOf(path) + "." + std::to_string(::getpid()) + "." +
                          std::to_string(serial.fetch_add(1)) + ".tmp";
  try {
    auto xf = cellTransform(frame);
    openvdb::GridPtrVec grids;
    auto add = [&](openvdb::GridBase::Ptr g) {
      g->setTransform(xf);
      g->setSaveFloatAsHalf(options.half_float);
      addMetadata(*g, frame.metadata);
      grids.push_back(g);
    };
    add(floatGrid("density", frame.density, frame, options, openvdb::GRID_FOG_VOLUME));
    if (frame.velocity[0].data) add(velocityGrid(frame, options));
    if (frame.pressure.data) add(floatGrid("pressure", frame.pressure, frame, options, openvdb::GRID_UNKNOWN));
    openvdb::MetaMap file_meta;
    addMetadata(file_meta, frame.metadata);
    openvdb::io::File file(tmp);
    file.setCompression(compressionFlags(options.compression));
    file.write(grids, file_meta);
    file.close();
    deriveFileUuid(tmp);
    syncPath(tmp, false);
  } catch (const openvdb::Exception& e) {
    std::remove(tmp.c_str());
    throw VdbError("OpenVDB could not write '" + path + "': " + e.what());
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp.c_str());
    throw VdbError("cannot rename the finished file to '" + path + "': " + errnoText(err));
  }
  syncPath(folder, true);
}

std::vector<std::string> supportedCompressions() {
  std::vector<std::string> out{"none"};
#ifdef OPENVDB_USE_ZLIB
  out.push_back("zip");
#endif
#ifdef OPENVDB_USE_BLOSC
  out.push_back("blosc");
#endif
  return out;
}

std::string openvdbVersion() { return openvdb::getLibraryVersionString(); }

}  // namespace hf::io
