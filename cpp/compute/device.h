// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The device the engine's stages run on, behind one interface with two implementations: gl/
// (OpenGL 4.5 compute shaders on a headless EGL context: a GPU, or Mesa's llvmpipe) and cpu/ (the
// same kernels compiled as C++, run by a thread pool). The stages (fluid/, obstacle/, force/,
// emitter/) speak only to the objects of this layer: textures, storage buffers, programs, a
// stage timer; each object is made by the device current on the calling thread (the worker's,
// compute_worker.h), so the dispatching code is the same for both.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace hf::compute {

// Which implementation a device is.
enum class Backend { Gpu, Cpu };

// The name the settings and reports use: "gpu" or "cpu".
const char* backendName(Backend b);

// What a device runs on, as reported to the user.
struct DeviceInfo {
  Backend backend = Backend::Gpu;
  std::string renderer;      // GL_RENDERER (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"), or the CPU kernels' description
  std::string vendor;        // GL_VENDOR, or the CPU's vendor
  std::string version;       // GL_VERSION, or the CPU kernels' instruction set
  std::string egl_vendor;    // EGL_VENDOR of the display ("" on the CPU)
  std::string platform;      // "device" (EGL_EXT_platform_device), "surfaceless", or "cpu"
  int device_index = -1;     // index in eglQueryDevicesEXT's list; -1 for surfaceless and the CPU
  bool software = false;     // the GL renderer runs on the CPU (Mesa llvmpipe / softpipe); false for the CPU backend
  int threads = 0;           // CPU backend: the threads a dispatch runs on; 0 on the GPU
  std::size_t memory_bytes = 0;  // memory free when the device was made (the host's MemAvailable
                                 // for a software or CPU device); 0 = unknown
  int max_3d_texture_size = 0;   // cells per axis a field may have
  std::size_t max_storage_block_bytes = 0;  // the largest storage buffer a program can address
  std::string warning;           // "" or why this device may not be what the user wants
};

enum class TexelFormat { R32F, RGBA32F, R8UI };

// How a stage uses an image it binds.
enum class Access { Read, Write, ReadWrite };

// Bytes per texel of a format.
std::size_t texelBytes(TexelFormat format);

using Defines = std::vector<std::pair<std::string, std::string>>;

// ---- what each implementation provides (the front objects of this layer own one each) ----

class TextureImpl {
 public:
  virtual ~TextureImpl() = default;
  virtual void bindImage(unsigned unit, Access access) const = 0;
  virtual void clear() = 0;
  virtual void download(void* dst, std::size_t bytes) const = 0;  // whole texture, x fastest
  virtual void upload(const void* src, std::size_t bytes) = 0;
  // Texture3D::changedOnlyIn: what a device that derives data from a texture may use (the GPU
  // derives nothing).
  virtual void changedOnlyIn(const glm::ivec3& origin, const glm::ivec3& extent) {
    (void)origin;
    (void)extent;
  }
};

class BufferImpl {
 public:
  virtual ~BufferImpl() = default;
  virtual void bind(unsigned binding) const = 0;
  virtual void clear() = 0;
  virtual void download(void* dst, std::size_t bytes, std::size_t offset) const = 0;
  virtual void upload(const void* src, std::size_t bytes, std::size_t offset) = 0;
};

class ProgramImpl {
 public:
  virtual ~ProgramImpl() = default;
  virtual glm::ivec3 localSize() const = 0;
  virtual int imageUnits() const = 0;
  virtual void setInt(const char* uniform, int v) = 0;
  virtual void setUint(const char* uniform, unsigned v) = 0;
  virtual void setFloat(const char* uniform, float v) = 0;
  virtual void setIVec3(const char* uniform, const glm::ivec3& v) = 0;
  virtual void setVec3(const char* uniform, const glm::vec3& v) = 0;
  virtual void setMat4(const char* uniform, const glm::mat4& v) = 0;
  // Runs the program over `invocations`; what it wrote is visible to the next stage and to
  // read-backs when it returns (GL: the memory barrier its writes need).
  virtual void dispatch(const glm::ivec3& invocations) = 0;
  // One dispatch of a series (dispatchSeries).
  struct SeriesDispatch {
    ProgramImpl* program;
    glm::ivec3 invocations;
  };
  // Called on the first entry's program: each entry's program over its invocations in turn, with
  // the images and buffers bound now: the result of those dispatches in that order. A device may
  // run them in one pass where it keeps that result (the CPU: red-black sweeps of one level, each
  // a plane behind the one before).
  virtual void dispatchSeries(const std::vector<SeriesDispatch>& series) {
    for (const SeriesDispatch& d : series) d.program->dispatch(d.invocations);
  }
};

class TimerImpl {
 public:
  virtual ~TimerImpl() = default;
  virtual void begin() = 0;
  virtual void mark(const std::string& stage) = 0;
  virtual std::vector<std::pair<std::string, double>> collect() = 0;
};

// One device: the factory of the objects above, current on the thread that runs its work.
class Device {
 public:
  virtual ~Device() = default;
  virtual const DeviceInfo& info() const = 0;
  virtual std::unique_ptr<TextureImpl> makeTexture(const glm::ivec3& size, TexelFormat format,
                                                   const std::string& label) = 0;
  virtual std::unique_ptr<BufferImpl> makeBuffer(std::size_t bytes, const std::string& label) = 0;
  // `file` names a kernel in shaders/ (e.g. "jacobi.comp"); `defines` its variant.
  virtual std::unique_ptr<ProgramImpl> makeProgram(const std::string& file, const Defines& defines) = 0;
  virtual std::unique_ptr<TimerImpl> makeTimer() = 0;
};

// The device current on this thread; throws hf::Error when there is none (an engine object made
// outside a worker's thread).
Device& currentDevice();

// Makes `device` current on this thread for the scope's lifetime (the worker's loop).
class DeviceScope {
 public:
  explicit DeviceScope(Device& device);
  ~DeviceScope();
  DeviceScope(const DeviceScope&) = delete;
  DeviceScope& operator=(const DeviceScope&) = delete;

 private:
  Device* previous_;
};

// Counts since the process started (every device): dispatches, the invocations they launched
// (GL: workgroups x local size, the padding of partial workgroups included) and the
// device-to-host syncs (read-backs that wait for the device). The benchmark reports them per step.
struct DispatchCounters {
  std::uint64_t dispatches = 0;
  std::uint64_t invocations = 0;
  std::uint64_t syncs = 0;
};
DispatchCounters dispatchCounters();
void countDispatch(std::uint64_t invocations);
void countSync();

}  // namespace hf::compute
