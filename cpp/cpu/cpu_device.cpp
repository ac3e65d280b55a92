// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/cpu_device.h"

#include <sched.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "common/error.h"
#include "common/host_memory.h"
#include "common/thread_priority.h"
#include "cpu/float_mode.h"
#include "cpu/kernel.h"
#include "cpu/regular_rows.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {
namespace {

// Cells per axis a CPU field may have; its texels must also stay below 2^31 (32-bit indices).
constexpr int kMaxAxisTexels = 4096;
constexpr std::size_t kMaxTexels = (std::size_t(1) << 31) - 1;
constexpr std::size_t kMaxBufferBytes = std::size_t(1) << 31;
constexpr std::size_t kAlignment = 64;  // a cache line

ImageFormat imageFormat(compute::TexelFormat f) {
  switch (f) {
    case compute::TexelFormat::R32F: return ImageFormat::R32F;
    case compute::TexelFormat::RGBA32F: return ImageFormat::RGBA32F;
    case compute::TexelFormat::R8UI: return ImageFormat::R8UI;
  }
  return ImageFormat::R32F;
}

// Zeroed, cache-line aligned host memory (RAII), with `guard` zeroed bytes before and after that
// nothing writes (a texture's guard band: glsl::UncheckedImage).
class HostBlock {
 public:
  HostBlock(std::size_t bytes, std::size_t guard, const std::string& label)
      : bytes_(bytes), guard_((guard + kAlignment - 1) / kAlignment * kAlignment) {
    const std::size_t total = (bytes + kAlignment - 1) / kAlignment * kAlignment + 2 * guard_;
    base_ = static_cast<unsigned char*>(std::aligned_alloc(kAlignment, total == 0 ? kAlignment : total));
    if (base_ == nullptr) {
      throw GlError("allocating '" + label + "' (" + std::to_string(bytes >> 20) +
                    " MiB of host memory) failed: lower the resolution");
    }
    std::memset(base_, 0, total == 0 ? kAlignment : total);
  }
  ~HostBlock() { std::free(base_); }
  HostBlock(const HostBlock&) = delete;
  HostBlock& operator=(const HostBlock&) = delete;
  unsigned char* data() const { return base_ + guard_; }
  std::size_t bytes() const { return bytes_; }

 private:
  unsigned char* base_ = nullptr;
  std::size_t bytes_ = 0;
  std::size_t guard_ = 0;
};

class CpuDevice;

class CpuTexture final : public compute::TextureImpl {
 public:
  CpuTexture(Bindings& bindings, const glm::ivec3& size, compute::TexelFormat format, const std::string& label)
      : bindings_(bindings),
        block_(checkedBytes(size, format, label),
               (static_cast<std::size_t>(size.x) * size.y + size.x + 1) * compute::texelBytes(format), label),
        size_(size), format_(format) {
    renewVersion();
    noted_version_ = version_;
  }
  ~CpuTexture() override {
    for (ImageBinding& b : bindings_.images) {
      if (b.data == block_.data()) b = ImageBinding{};  // a unit left bound to freed memory reads nothing
    }
  }
  void bindImage(unsigned unit, compute::Access access) const override {
    if (unit >= bindings_.images.size()) throw Error("image unit " + std::to_string(unit) + " is past the device's units");
    if (access != compute::Access::Read) renewVersion();
    ImageBinding& b = bindings_.images[unit];
    b.version = version_;
    b.change = &note_;
    b.data = block_.data();
    b.size = size_;
    b.stride_y = size_.x;
    b.stride_z = size_.x * size_.y;
    b.plane = format_ == compute::TexelFormat::RGBA32F ? texels() : 0;
    b.format = imageFormat(format_);
  }
  void clear() override {
    std::memset(block_.data(), 0, block_.bytes());
    renewVersion();
    noted_version_ = 0;  // written everywhere, whatever the next word says
  }
  void changedOnlyIn(const glm::ivec3& origin, const glm::ivec3& extent) override {
    note_ = ChangeNote{noted_version_, version_, origin, extent};
    noted_version_ = version_;
  }
  // The caller's layout is x fastest with a texel's channels together; a 4-channel texture keeps
  // them in planes (glsl.h), so those two are reordered.
  void download(void* dst, std::size_t bytes) const override {
    if (format_ == compute::TexelFormat::RGBA32F) {
      const float* planes = reinterpret_cast<const float*>(block_.data());
      float* out = static_cast<float*>(dst);
      const std::size_t n = texels();
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t ch = 0; ch < 4; ++ch) out[4 * i + ch] = planes[ch * n + i];
      }
    } else {
      std::memcpy(dst, block_.data(), bytes);
    }
    compute::countSync();
  }
  void upload(const void* src, std::size_t bytes) override {
    renewVersion();
    noted_version_ = 0;  // written everywhere, whatever the next word says
    if (format_ == compute::TexelFormat::RGBA32F) {
      float* planes = reinterpret_cast<float*>(block_.data());
      const float* in = static_cast<const float*>(src);
      const std::size_t n = texels();
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t ch = 0; ch < 4; ++ch) planes[ch * n + i] = in[4 * i + ch];
      }
    } else {
      std::memcpy(block_.data(), src, bytes);
    }
  }

 private:
  static std::size_t checkedBytes(const glm::ivec3& size, compute::TexelFormat format, const std::string& label) {
    const std::size_t texels = static_cast<std::size_t>(size.x) * size.y * size.z;
    if (size.x < 1 || size.y < 1 || size.z < 1 || size.x > kMaxAxisTexels || size.y > kMaxAxisTexels ||
        size.z > kMaxAxisTexels || texels > kMaxTexels) {
      throw GlError("texture '" + label + "': " + std::to_string(size.x) + " x " + std::to_string(size.y) + " x " +
                    std::to_string(size.z) + " texels is outside what the CPU device holds (1.." +
                    std::to_string(kMaxAxisTexels) + " per axis, below 2^31 in all): lower the resolution");
    }
    return texels * compute::texelBytes(format);
  }

  std::size_t texels() const { return static_cast<std::size_t>(size_.x) * size_.y * size_.z; }

  // A new version for these contents, also on every unit the texture is bound to now (one bound
  // for reading may be read again after a write through another unit, without a new bind).
  void renewVersion() const {
    static std::atomic<std::uint64_t> counter{0};
    version_ = counter.fetch_add(1, std::memory_order_relaxed) + 1;
    for (ImageBinding& b : bindings_.images) {
      if (b.data == block_.data()) b.version = version_;
    }
  }

  Bindings& bindings_;
  HostBlock block_;
  glm::ivec3 size_;
  compute::TexelFormat format_;
  mutable std::uint64_t version_ = 0;
  std::uint64_t noted_version_ = 0;  // the version at the last changedOnlyIn (0: a clear or upload since)
  ChangeNote note_;
};

class CpuBuffer final : public compute::BufferImpl {
 public:
  CpuBuffer(Bindings& bindings, std::size_t bytes, const std::string& label)
      : bindings_(bindings), block_(bytes, 0, label) {}
  ~CpuBuffer() override {
    for (BufferBinding& b : bindings_.buffers) {
      if (b.data == block_.data()) b = BufferBinding{};
    }
  }
  void bind(unsigned binding) const override {
    if (binding >= bindings_.buffers.size()) {
      throw Error("storage buffer binding " + std::to_string(binding) + " is past the device's bindings");
    }
    bindings_.buffers[binding] = {block_.data(), block_.bytes()};
  }
  void clear() override { std::memset(block_.data(), 0, block_.bytes()); }
  void download(void* dst, std::size_t bytes, std::size_t offset) const override {
    std::memcpy(dst, block_.data() + offset, bytes);
    compute::countSync();
  }
  void upload(const void* src, std::size_t bytes, std::size_t offset) override {
    std::memcpy(block_.data() + offset, src, bytes);
  }

 private:
  Bindings& bindings_;
  HostBlock block_;
};

class CpuProgram final : public compute::ProgramImpl {
 public:
  CpuProgram(Bindings& bindings, ThreadPool& pool, const std::string& file, const compute::Defines& defines)
      : bindings_(bindings), pool_(pool), file_(file), kernel_(kernelRegistry().make(file, defines)),
        local_size_(localSizeOf(defines)) {
    for (const auto& image : kernel_->slots().images) {
      bool seen = false;
      for (const auto& other : kernel_->slots().images) {
        if (&other == &image) break;
        if (other.unit == image.unit) seen = true;
      }
      if (!seen) ++image_units_;
    }
  }

  glm::ivec3 localSize() const override { return local_size_; }
  int imageUnits() const override { return image_units_; }
  void setInt(const char* name, int v) override { set(name, KernelSlots::UniformType::Int, &v, sizeof v); }
  void setUint(const char* name, unsigned v) override { set(name, KernelSlots::UniformType::Uint, &v, sizeof v); }
  void setFloat(const char* name, float v) override { set(name, KernelSlots::UniformType::Float, &v, sizeof v); }
  void setIVec3(const char* name, const glm::ivec3& v) override {
    set(name, KernelSlots::UniformType::IVec3, &v, sizeof v);
  }
  void setVec3(const char* name, const glm::vec3& v) override { set(name, KernelSlots::UniformType::Vec3, &v, sizeof v); }
  void setMat4(const char* name, const glm::mat4& v) override { set(name, KernelSlots::UniformType::Mat4, &v, sizeof v); }

  void dispatch(const glm::ivec3& invocations) override {
    FlushDenormals flush;  // cpu/float_mode.h
    bindSlots();
    kernel_->run(invocations, local_size_, bindings_, pool_);
    countDispatch(invocations);
  }

  void dispatchSeries(const std::vector<SeriesDispatch>& series) override {
    FlushDenormals flush;  // cpu/float_mode.h
    std::vector<CpuProgram*> programs;
    std::vector<CpuKernel*> kernels;
    for (const SeriesDispatch& d : series) {
      auto* p = dynamic_cast<CpuProgram*>(d.program);
      if (p == nullptr) {
        compute::ProgramImpl::dispatchSeries(series);
        return;
      }
      programs.push_back(p);
      kernels.push_back(p->kernel_.get());
    }
    for (CpuProgram* p : programs) p->bindSlots();
    if (series.size() > 1 && kernel_->runSeries(kernels, bindings_, pool_)) {
      for (std::size_t i = 0; i < series.size(); ++i) programs[i]->countDispatch(series[i].invocations);
      return;
    }
    for (std::size_t i = 0; i < series.size(); ++i) programs[i]->dispatch(series[i].invocations);
  }

 private:
  // The bound images and buffers into the kernel's slots.
  void bindSlots() {
    KernelSlots& slots = kernel_->slots();
    for (const auto& image : slots.images) {
      const ImageBinding& bound = bindings_.images[static_cast<std::size_t>(image.unit)];
      // Nothing bound, or a texture of another format (a unit left from another stage that this
      // variant declares but does not use): the kernel sees an empty image (loads give 0).
      *image.target = (bound.data != nullptr && bound.format == image.format) ? bound : ImageBinding{};
      image.target->format = image.format;
    }
    for (const auto& buffer : slots.buffers) *buffer.target = bindings_.buffers[static_cast<std::size_t>(buffer.binding)];
  }

  static void countDispatch(const glm::ivec3& invocations) {
    compute::countDispatch(static_cast<std::uint64_t>(invocations.x) * static_cast<std::uint64_t>(invocations.y) *
                           static_cast<std::uint64_t>(invocations.z));
  }

  void set(const char* name, KernelSlots::UniformType type, const void* value, std::size_t bytes) {
    // Every struct of the kernel's runner has it (a runner may hold a checked and an unchecked
    // build); a uniform the kernel does not have is ignored, as GL ignores location -1.
    for (const auto& u : kernel_->slots().uniforms) {
      if (std::strcmp(u.name, name) != 0) continue;
      if (u.type != type) throw Error(file_ + ": uniform " + name + " set with a value of another type");
      std::memcpy(u.target, value, bytes);
    }
  }

  Bindings& bindings_;
  ThreadPool& pool_;
  std::string file_;
  std::unique_ptr<CpuKernel> kernel_;
  glm::ivec3 local_size_;
  int image_units_ = 0;
};

class CpuStageTimer final : public compute::TimerImpl {
 public:
  void begin() override {
    stages_.clear();
    last_ = std::chrono::steady_clock::now();
    started_ = true;
  }
  void mark(const std::string& stage) override {
    if (!started_) return;
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    for (auto& s : stages_) {
      if (s.first == stage) {
        s.second += ms;
        return;
      }
    }
    stages_.emplace_back(stage, ms);
  }
  std::vector<std::pair<std::string, double>> collect() override { return stages_; }

 private:
  std::vector<std::pair<std::string, double>> stages_;
  std::chrono::steady_clock::time_point last_;
  bool started_ = false;
};

class CpuDevice final : public compute::Device {
 public:
  CpuDevice(int threads, bool x86_v3) : pool_(threads) {
    bindings_.x86_v3 = x86_v3;
    bindings_.regular_rows = &regular_rows_;
    info_.backend = compute::Backend::Cpu;
    info_.threads = pool_.threads();
    info_.renderer = std::string("hapticfluid CPU kernels (") + (x86_v3 ? "AVX2" : "baseline") + "), " +
                     std::to_string(pool_.threads()) + " thread" + (pool_.threads() == 1 ? "" : "s");
    info_.vendor = "hapticfluid";
    info_.version = x86_v3 ? "C++ kernels, x86-64-v3 (AVX2, FMA)" : "C++ kernels, x86-64 baseline";
    info_.platform = "cpu";
    info_.memory_bytes = static_cast<std::size_t>(hostAvailableKb()) * 1024;
    info_.max_3d_texture_size = kMaxAxisTexels;
    info_.max_storage_block_bytes = kMaxBufferBytes;
  }
  const compute::DeviceInfo& info() const override { return info_; }
  compute::DeviceInfo& mutableInfo() { return info_; }
  std::unique_ptr<compute::TextureImpl> makeTexture(const glm::ivec3& size, compute::TexelFormat format,
                                                    const std::string& label) override {
    return std::make_unique<CpuTexture>(bindings_, size, format, label);
  }
  std::unique_ptr<compute::BufferImpl> makeBuffer(std::size_t bytes, const std::string& label) override {
    return std::make_unique<CpuBuffer>(bindings_, bytes, label);
  }
  std::unique_ptr<compute::ProgramImpl> makeProgram(const std::string& file, const compute::Defines& defines) override {
    return std::make_unique<CpuProgram>(bindings_, pool_, file, defines);
  }
  std::unique_ptr<compute::TimerImpl> makeTimer() override { return std::make_unique<CpuStageTimer>(); }

 private:
  Bindings bindings_;
  ThreadPool pool_;
  RegularRows regular_rows_;
  compute::DeviceInfo info_;
};

int coresAvailable() {
#if defined(__linux__)
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    const int n = CPU_COUNT(&set);
    if (n > 0) return n;
  }
#endif
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? static_cast<int>(n) : 1;
}

}  // namespace

int resolveThreads(int requested) {
  auto check = [](long long n, const std::string& from) {
    if (n < 0 || n > kMaxThreads) {
      throw InvalidArgument(from + " must be 0 (one per core) to " + std::to_string(kMaxThreads) + ", got " +
                            std::to_string(n));
    }
    return static_cast<int>(n);
  };
  int n = check(requested, "cpu_threads");
  if (n == 0) {
    if (const char* env = std::getenv(kCpuThreadsEnv); env != nullptr && *env != '\0') {
      char* end = nullptr;
      const long long v = std::strtoll(env, &end, 10);
      if (end == env || *end != '\0') {
        throw InvalidArgument(std::string(kCpuThreadsEnv) + " must be a whole number of threads, got '" + env + "'");
      }
      n = check(v, kCpuThreadsEnv);
    }
  }
  return n == 0 ? coresAvailable() : n;
}

std::unique_ptr<compute::Device> makeCpuDevice(int threads, std::optional<int> niceness, std::optional<bool> x86_v3) {
  const int n = resolveThreads(threads);
  const std::string refused = lowerCurrentThreadPriority(niceness.value_or(0));
#if defined(__linux__)
  nameCurrentThread("hf-cpu");  // the pool's threads inherit the name and the niceness
#endif
  if (x86_v3 && *x86_v3 && !cpuHasX86V3()) throw InvalidArgument("this CPU cannot run the x86-64-v3 (AVX2) kernels");
  auto device = std::make_unique<CpuDevice>(n, x86_v3.value_or(cpuHasX86V3()));
  if (!refused.empty()) device->mutableInfo().warning = "thread priority: " + refused;
  return device;
}

}  // namespace hf::cpu
