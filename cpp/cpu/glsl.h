// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The C++ side of the GLSL subset the kernels in shaders/ are written in, so that one source of
// each stage compiles both as a compute shader and as C++ (the way Blender's Cycles writes one
// kernel source against per-device headers). GLM supplies GLSL's types and functions under
// GLSL's names; this header adds what GLM lacks: images and storage buffers with GLSL's access
// rules (a load outside the image gives 0, a store outside it is dropped), atomics, and the
// declaration macros the shaders use for their bindings (cpu/kernel_begin.h; their GLSL
// definitions are in shaders/common.glsl):
//
//   IMAGE_RW(fmt, unit, name)  IMAGE_RO  IMAGE_WO     float images (r32f, rgba32f)
//   UIMAGE_RW(fmt, unit, name) UIMAGE_RO UIMAGE_WO    unsigned images (r8ui)
//   BUFFER_RW(block, type, binding, name) BUFFER_RO BUFFER_WO   std430 storage buffers
//   UNIFORM(type, name)
//   LOCAL_SIZE(x, y, z)         the workgroup shape (C++ ignores it: see cpu/kernel.h)
//
// A shader's `main()` becomes a member function taking the invocation (`gl_GlobalInvocationID`
// and the rest are members of it), so one kernel object serves every thread of a dispatch.
// Float literals in shared code carry the `f` suffix (GLSL 4 accepts it), so C++ computes in
// float as the GPU does.
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace hf::cpu {

enum class ImageFormat { R32F, RGBA32F, R8UI };

// A texture's word on where its contents changed (compute::Texture3D::changedOnlyIn): from the
// version `from` to the version `to` (ImageBinding::version) only texels in [origin, origin +
// extent) were written. `from` is 0 (no version) where a clear or an upload came between.
struct ChangeNote {
  std::uint64_t from = 0;
  std::uint64_t to = 0;
  glm::ivec3 origin{0};
  glm::ivec3 extent{0};
};

// A bound image: the texels of a texture of the CPU backend, x fastest.
struct ImageBinding {
  void* data = nullptr;
  glm::ivec3 size{0};
  int stride_y = 0;  // texels from one row to the next (size.x)
  int stride_z = 0;  // texels from one slice to the next (size.x * size.y); below 2^31
  // A 4-channel image is kept as 4 planes, one per channel, this many floats apart (so that row
  // loops load each channel contiguously); 0 for 1-channel images.
  std::size_t plane = 0;
  ImageFormat format = ImageFormat::R32F;
  // The contents' version: a number no other contents of any texture had, renewed whenever the
  // texture may have been written (bound writable, cleared, uploaded), so that a runner may keep
  // what it derived from an image it only reads (mg_smooth's regular rows) until it changes.
  std::uint64_t version = 0;
  // The texture's last Texture3D::changedOnlyIn (null: none, or not a texture of this device).
  const ChangeNote* change = nullptr;
};

struct BufferBinding {
  void* data = nullptr;
  std::size_t bytes = 0;
};

class KernelBase;

// Where a kernel's images, buffers and uniforms are, by unit, binding and name: filled once, as
// the kernel object is made, by the members the declaration macros define.
struct KernelSlots {
  struct Image {
    int unit;
    const char* name;
    ImageFormat format;
    ImageBinding* target;
  };
  struct Buffer {
    int binding;
    const char* name;
    BufferBinding* target;
  };
  enum class UniformType { Int, Uint, Float, IVec2, IVec3, Vec3, Vec4, Mat4 };
  struct Uniform {
    const char* name;
    UniformType type;
    void* target;
  };
  std::vector<Image> images;
  std::vector<Buffer> buffers;
  std::vector<Uniform> uniforms;
};

class KernelBase {
 public:
  explicit KernelBase(KernelSlots* slots) : hf_slots_(slots) {}
  // A copy runs like the original (a runner may copy a kernel into a local so that the compiler
  // keeps its bound images and uniforms in registers) but registers nothing.
  KernelBase(const KernelBase&) = default;
  KernelBase& operator=(const KernelBase&) = delete;
  KernelSlots& hf_slots() { return *hf_slots_; }

 private:
  KernelSlots* hf_slots_;
};

namespace glsl {

using namespace glm;  // vec3, ivec3, mix, clamp, ... under their GLSL names
using uint = unsigned int;

// Each format's texels and how a texel at index i is read and written.
struct r32f {
  using value = vec4;
  static constexpr ImageFormat format = ImageFormat::R32F;
  static value load(const ImageBinding& im, int i) { return value(static_cast<const float*>(im.data)[i], 0.0f, 0.0f, 1.0f); }
  static void store(const ImageBinding& im, int i, const value& v) { static_cast<float*>(im.data)[i] = v.x; }
};
struct rgba32f {
  using value = vec4;
  static constexpr ImageFormat format = ImageFormat::RGBA32F;
  static value load(const ImageBinding& im, int i) {
    const float* p = static_cast<const float*>(im.data) + i;
    return value(p[0], p[im.plane], p[2 * im.plane], p[3 * im.plane]);
  }
  static void store(const ImageBinding& im, int i, const value& v) {
    float* p = static_cast<float*>(im.data) + i;
    p[0] = v.x;
    p[im.plane] = v.y;
    p[2 * im.plane] = v.z;
    p[3 * im.plane] = v.w;
  }
};
struct r8ui {
  using value = uvec4;
  static constexpr ImageFormat format = ImageFormat::R8UI;
  static value load(const ImageBinding& im, int i) { return value(static_cast<const std::uint8_t*>(im.data)[i], 0u, 0u, 1u); }
  static void store(const ImageBinding& im, int i, const value& v) {
    static_cast<std::uint8_t*>(im.data)[i] = static_cast<std::uint8_t>(v.x);
  }
};

// One image uniform of a kernel (IMAGE_* / UIMAGE_*).
template <class Format>
struct Image : ImageBinding {
  Image(KernelBase* k, int unit, const char* name) {
    k->hf_slots().images.push_back({unit, name, Format::format, this});
    format = Format::format;
  }
  bool contains(const ivec3& c) const {
    return static_cast<unsigned>(c.x) < static_cast<unsigned>(size.x) &&
           static_cast<unsigned>(c.y) < static_cast<unsigned>(size.y) &&
           static_cast<unsigned>(c.z) < static_cast<unsigned>(size.z);
  }
  int index(const ivec3& c) const { return c.x + stride_y * c.y + stride_z * c.z; }
};

// The same image where the kernel's runner has proven every access in range (cpu/kernel.h:
// InteriorRunner, UncheckedRunner): no bounds test. A CPU texture has a guard band of a slice
// and a row of zeros on each side, so even an access one slice out reads memory it owns.
template <class Format>
struct UncheckedImage : Image<Format> {
  using Image<Format>::Image;
};

template <class Format>
typename Format::value imageLoad(const UncheckedImage<Format>& image, const ivec3& c) {
  return Format::load(image, image.index(c));
}

template <class Format>
void imageStore(const UncheckedImage<Format>& image, const ivec3& c, const typename Format::value& v) {
  Format::store(image, image.index(c), v);
}

template <class Format>
typename Format::value imageLoad(const Image<Format>& image, const ivec3& c) {
  if (!image.contains(c)) return typename Format::value(0);
  return Format::load(image, image.index(c));
}

template <class Format>
void imageStore(const Image<Format>& image, const ivec3& c, const typename Format::value& v) {
  if (image.contains(c)) Format::store(image, image.index(c), v);
}

template <class Format>
ivec3 imageSize(const Image<Format>& image) {
  return image.size;
}

// One storage buffer of a kernel (BUFFER_*): its array, indexed like GLSL's `name[i]`.
template <class T>
struct Buffer : BufferBinding {
  Buffer(KernelBase* k, int binding, const char* name) { k->hf_slots().buffers.push_back({binding, name, this}); }
  T& operator[](std::size_t i) const { return static_cast<T*>(data)[i]; }
  std::size_t length() const { return bytes / sizeof(T); }
};

template <class T>
struct UniformTypeOf;
template <> struct UniformTypeOf<int> { static constexpr auto value = KernelSlots::UniformType::Int; };
template <> struct UniformTypeOf<uint> { static constexpr auto value = KernelSlots::UniformType::Uint; };
template <> struct UniformTypeOf<float> { static constexpr auto value = KernelSlots::UniformType::Float; };
template <> struct UniformTypeOf<ivec2> { static constexpr auto value = KernelSlots::UniformType::IVec2; };
template <> struct UniformTypeOf<ivec3> { static constexpr auto value = KernelSlots::UniformType::IVec3; };
template <> struct UniformTypeOf<vec3> { static constexpr auto value = KernelSlots::UniformType::Vec3; };
template <> struct UniformTypeOf<vec4> { static constexpr auto value = KernelSlots::UniformType::Vec4; };
template <> struct UniformTypeOf<mat4> { static constexpr auto value = KernelSlots::UniformType::Mat4; };

// Registers the uniform member it follows (UNIFORM); holds nothing itself.
struct UniformSlot {
  template <class T>
  UniformSlot(KernelBase* k, const char* name, T* target) {
    k->hf_slots().uniforms.push_back({name, UniformTypeOf<T>::value, target});
  }
};

// GLSL's atomicAdd on a storage-buffer element: returns the value before.
inline int atomicAdd(int& target, int value) { return __atomic_fetch_add(&target, value, __ATOMIC_RELAXED); }
inline uint atomicAdd(uint& target, uint value) { return __atomic_fetch_add(&target, value, __ATOMIC_RELAXED); }

// What GLSL has and GLM does not name the same way.
inline float inversesqrt(float x) { return 1.0f / std::sqrt(x); }
inline bool isnan(float x) { return std::isnan(x); }
inline bool isinf(float x) { return std::isinf(x); }
inline bool isnan(double x) { return std::isnan(x); }
inline bool isinf(double x) { return std::isinf(x); }

// GROUP_SUM kernels: the running sums of one workgroup, one vec4 per part (writeGroupSumAt),
// added in invocation order (the GPU adds them as a tree: the same sum up to rounding).
struct GroupSums {
  static constexpr uint kMaxParts = 8;
  vec4 sums[kMaxParts];
  uint parts = 0;
  void add(const vec4& value, uint part) {
    sums[part] += value;
    if (part + 1 > parts) parts = part + 1;
  }
};

// Workgroup barriers have no C++ form: a kernel that needs them (reduce.comp, mg_coarsest.comp)
// is run on the CPU by a runner of its own that never calls its main().
[[noreturn]] void barrierUnavailable();
inline void barrier() { barrierUnavailable(); }
inline void memoryBarrierShared() {}

// The invocation a kernel's main runs for (GLSL's built-in inputs).
struct Invocation {
  uvec3 global_id{0u};
  uvec3 local_id{0u};
  uvec3 group_id{0u};
  uvec3 groups{1u};
  uint local_index = 0u;
  GroupSums* group = nullptr;  // GROUP_SUM kernels only
};

}  // namespace glsl
}  // namespace hf::cpu

