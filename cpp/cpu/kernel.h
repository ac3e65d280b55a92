// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// A kernel of shaders/ compiled as C++ (cpu/kernels/), and how the CPU device finds and runs it.
// A kernel file wraps each shader variant in a struct (its uniforms, images and buffers become
// members: cpu/glsl.h) and registers a runner for it under the shader's file name and the
// #defines that select the variant:
//   - InvocationRunner<K>: calls K's main() once per invocation, rows of invocations split over
//     the pool's threads (every kernel whose invocations write disjoint texels);
//   - GroupSumRunner<K>: the same per workgroup, for kernels that end in writeGroupSum (the
//     first level of a reduction): each workgroup's sum goes to partials[part * groups + group];
//   - a runner of the kernel's own, where the shader needs workgroup barriers or where a row loop
//     runs the shader's per-cell functions faster (its file says why).
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "compute/device.h"
#include "cpu/glsl.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {

// The image units and storage-buffer bindings the device has (GL 4.5's guaranteed minimums).
inline constexpr int kImageUnits = 8;
inline constexpr int kBufferBindings = 8;

struct Bindings {
  std::array<ImageBinding, kImageUnits> images{};
  std::array<BufferBinding, kBufferBindings> buffers{};
};

class CpuKernel {
 public:
  virtual ~CpuKernel() = default;
  virtual KernelSlots& slots() = 0;
  // Runs the kernel over `invocations` with its slots bound; `local_size` is the workgroup
  // shape its #defines give (GROUP_SUM kernels need it).
  virtual void run(const glm::ivec3& invocations, const glm::ivec3& local_size, const Bindings& bindings,
                   ThreadPool& pool) = 0;
};

// Below this many invocations a dispatch runs on the calling thread alone (waking the pool
// costs more than a small level of the multigrid).
inline constexpr long long kSerialInvocations = 4096;

template <class K>
class InvocationRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings&, ThreadPool& pool) override {
    const int rows = n.y * n.z;
    auto rowRange = [&](int begin, int end) {
      glsl::Invocation inv;
      for (int r = begin; r < end; ++r) {
        const unsigned y = static_cast<unsigned>(r % n.y), z = static_cast<unsigned>(r / n.y);
        for (int x = 0; x < n.x; ++x) {
          inv.global_id = glm::uvec3(static_cast<unsigned>(x), y, z);
          kernel_.hf_main(inv);
        }
      }
    };
    const long long total = static_cast<long long>(n.x) * rows;
    if (total < kSerialInvocations || rows == 1) {
      if (rows == 1 && total >= kSerialInvocations) {  // one long row (per vertex, per triangle)
        pool.parallelFor(n.x, [&](int begin, int end) {
          glsl::Invocation inv;
          for (int x = begin; x < end; ++x) {
            inv.global_id = glm::uvec3(static_cast<unsigned>(x), 0u, 0u);
            kernel_.hf_main(inv);
          }
        });
        return;
      }
      rowRange(0, rows);
      return;
    }
    pool.parallelFor(rows, rowRange);
  }

 private:
  KernelSlots slots_;
  K kernel_{&slots_};
};

template <class K>
class GroupSumRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3& local, const Bindings& bindings, ThreadPool& pool) override;

 private:
  KernelSlots slots_;
  K kernel_{&slots_};
};

// Writes one workgroup's sums (GroupSumRunner): partials[part * groups + group].
void storeGroupSums(const glsl::GroupSums& sums, unsigned group, unsigned groups, const BufferBinding& partials);

template <class K>
void GroupSumRunner<K>::run(const glm::ivec3& n, const glm::ivec3& local, const Bindings& bindings,
                            ThreadPool& pool) {
  const glm::ivec3 groups = (n + local - 1) / local;
  const int count = groups.x * groups.y * groups.z;
  const BufferBinding& partials = bindings.buffers[0];
  pool.parallelFor(count, [&](int begin, int end) {
    glsl::Invocation inv;
    inv.groups = glm::uvec3(groups);
    for (int g = begin; g < end; ++g) {
      const glm::ivec3 gid(g % groups.x, (g / groups.x) % groups.y, g / (groups.x * groups.y));
      glsl::GroupSums sums{};
      inv.group = &sums;
      inv.group_id = glm::uvec3(gid);
      unsigned index = 0;
      for (int z = 0; z < local.z; ++z) {
        for (int y = 0; y < local.y; ++y) {
          for (int x = 0; x < local.x; ++x, ++index) {
            inv.local_id = glm::uvec3(static_cast<unsigned>(x), static_cast<unsigned>(y), static_cast<unsigned>(z));
            inv.local_index = index;
            inv.global_id = glm::uvec3(gid * local) + inv.local_id;
            kernel_.hf_main(inv);  // every invocation of the group, as on the GPU (each calls writeGroupSum)
          }
        }
      }
      storeGroupSums(sums, static_cast<unsigned>(g), static_cast<unsigned>(count), partials);
    }
  });
}

// The kernels the CPU device can run, by shader file and the #defines that select a variant
// (the workgroup-shape #defines are not part of the key).
struct KernelEntry {
  std::string file;
  compute::Defines defines;  // sorted by name
  std::function<std::unique_ptr<CpuKernel>()> make;
};

class KernelRegistry {
 public:
  template <class Runner>
  void add(const std::string& file, compute::Defines defines) {
    addEntry(file, std::move(defines), [] { return std::unique_ptr<CpuKernel>(new Runner()); });
  }
  // The runner of `file` with `defines` (workgroup-shape names ignored); throws hf::Error naming
  // both when this build has no such kernel.
  std::unique_ptr<CpuKernel> make(const std::string& file, const compute::Defines& defines) const;

 private:
  void addEntry(const std::string& file, compute::Defines defines, std::function<std::unique_ptr<CpuKernel>()> make);
  std::vector<KernelEntry> entries_;
};

// Every kernel of this build (cpu/kernels/kernel_list.cpp).
const KernelRegistry& kernelRegistry();

// The workgroup shape a program's #defines give: WG_X/WG_Y/WG_Z, ROW_X/ROW_Y, WG_LINEAR,
// REDUCE_SIZE or COARSEST; (1, 1, 1) when none.
glm::ivec3 localSizeOf(const compute::Defines& defines);

}  // namespace hf::cpu
