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
//   - InteriorRunner<K, KU> / UncheckedRunner<KU>: the same with the bounds tests left out where
//     the runner proves every access in range (KU: the shader built with glsl::UncheckedImage);
//   - SimdRowRunner<KU, Body> / InteriorSimdRowRunner<KU, KI, Body>: a kernel file's vectorized
//     row loop over the shader's per-cell function (KI: built with HF_CLAMP_FREE, for the cells
//     whose neighbours are all in the grid);
//   - a runner of the kernel's own, where the shader needs workgroup barriers or where a row loop
//     runs the shader's per-cell functions faster (its file says why).
#include <algorithm>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/glm.hpp>

#include "compute/device.h"
#include "cpu/glsl.h"
#include "cpu/thread_pool.h"

namespace hf::cpu {

// The image units and storage-buffer bindings the device has (GL 4.5's guaranteed minimums).
inline constexpr int kImageUnits = 8;
inline constexpr int kBufferBindings = 8;

class RegularRows;

struct Bindings {
  std::array<ImageBinding, kImageUnits> images{};
  std::array<BufferBinding, kBufferBindings> buffers{};
  bool x86_v3 = false;  // the device runs the x86-64-v3 build of every loop (see runBest)
  RegularRows* regular_rows = nullptr;  // the device's (cpu/regular_rows.h)
};

class CpuKernel {
 public:
  virtual ~CpuKernel() = default;
  virtual KernelSlots& slots() = 0;
  // Runs the kernel over `invocations` with its slots bound; `local_size` is the workgroup
  // shape its #defines give (GROUP_SUM kernels need it).
  virtual void run(const glm::ivec3& invocations, const glm::ivec3& local_size, const Bindings& bindings,
                   ThreadPool& pool) = 0;
  // The kernels of a series of dispatches (ProgramImpl::dispatchSeries; series[0] is this one), each
  // with its own slots bound, run in one pass where the kernel knows how: returns false, having run
  // nothing, where it does not.
  virtual bool runSeries(const std::vector<CpuKernel*>& /*series*/, const Bindings& /*bindings*/, ThreadPool& /*pool*/) {
    return false;
  }
};

// ---- instruction sets ------------------------------------------------------------------------
// Every runner's loop is compiled twice: for the x86-64 baseline and for x86-64-v3 (AVX2, FMA,
// BMI2), picked when the module loads by what the CPU has; the row loops vectorize 8 wide with
// the latter. The kernels are built with -ffp-contract=off, so both give the same bits.

// The environment variable that forces the baseline build ("baseline").
inline constexpr const char* kCpuIsaEnv = "HAPTICFLUID_CPU_ISA";

// True when this CPU runs the x86-64-v3 build and HAPTICFLUID_CPU_ISA does not say "baseline"
// (a device takes this when it is made unless told otherwise: cpu_device.h).
bool cpuHasX86V3();

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define HF_X86_V3 __attribute__((target("avx2,fma,bmi,bmi2,f16c,lzcnt,movbe,popcnt"), flatten))
template <class F>
HF_X86_V3 void runX86V3(const F& f) {
  f();
}
#endif

template <class F>
__attribute__((flatten)) void runBaseline(const F& f) {
  f();
}

// Runs f (a loop over cells, inlined) with the x86-64-v3 build when `x86_v3`, else the baseline.
template <class F>
void runBest(bool x86_v3, const F& f) {
#if defined(HF_X86_V3)
  if (x86_v3) {
    runX86V3(f);
    return;
  }
#endif
  runBaseline(f);
}

// `omp simd` on the runners' row loops in the kernel files (built with -fopenmp-simd and
// HF_CPU_KERNEL_FILE: cpu/CMakeLists.txt); nothing elsewhere, where the runners are not run.
#if defined(HF_CPU_KERNEL_FILE)
#define HF_OMP_SIMD _Pragma("omp simd")
#else
#define HF_OMP_SIMD
#endif

// Below this many invocations a dispatch runs on the calling thread alone: waking the pool costs
// more than it saves on a small grid or a coarse multigrid level, and a busy machine (Blender
// drawing beside a live session) may not run the second thread at once. Measured (2 cores, a
// 32^3 step, multigrid): 14.8 ms on one thread against 30 ms split over two at 4096.
inline constexpr long long kSerialInvocations = 65536;

// Calls row(y, z) for every row of the dispatch box `n` (or, for a single long row, chunk(x0,
// x1)), split over the pool's threads. `cells_per_invocation`: the cells one invocation works on
// (1, or a row stage's row length: RowLoopRunner), what the serial threshold counts.
template <class Row, class Chunk>
void forRows(const glm::ivec3& n, ThreadPool& pool, Row&& row, Chunk&& chunk, long long cells_per_invocation = 1) {
  const int rows = n.y * n.z;
  const long long total = static_cast<long long>(n.x) * rows * cells_per_invocation;
  if (rows == 1 && total >= kSerialInvocations) {  // one long row (per vertex, per triangle)
    pool.parallelFor(n.x, chunk);
    return;
  }
  auto range = [&](int begin, int end) {
    for (int r = begin; r < end; ++r) row(r % n.y, r / n.y);
  };
  if (total < kSerialInvocations) {
    range(0, rows);
  } else {
    pool.parallelFor(rows, range);
  }
}

// Calls row(k, y, z, x0, x1) for every row of the dispatch box `n` (x0..x1 its invocations; a
// single long row is cut into chunks), on the pool's threads, with the best instruction set. Each
// thread runs a copy k of the kernel: its bound images and uniforms are then locals the compiler
// can keep in registers.
template <class K, class Row>
void forEachRow(const glm::ivec3& n, ThreadPool& pool, bool x86_v3, const K& kernel, const Row& row,
                long long cells_per_invocation = 1) {
  forRows(
      n, pool,
      [&](int y, int z) {
        runBest(x86_v3, [&] {
          K k(kernel);
          row(k, y, z, 0, n.x);
        });
      },
      [&](int x0, int x1) {
        runBest(x86_v3, [&] {
          K k(kernel);
          row(k, 0, 0, x0, x1);
        });
      },
      cells_per_invocation);
}

template <class K>
inline void runInvocation(K& k, glsl::Invocation& inv, int x, int y, int z) {
  inv.global_id = glm::uvec3(static_cast<unsigned>(x), static_cast<unsigned>(y), static_cast<unsigned>(z));
  k.hf_main(inv);
}

// K's main() once per invocation. With K the shader's bounds-tested build (glsl::Image), every
// access is tested as GL does; as UncheckedRunner, K is its unchecked build (UncheckedImage), for a
// kernel whose every access is in range by its own construction (clamped coordinates, or a row
// loop over the grid with neighbours only across linked faces); a kernel file that uses it says why.
template <class K>
class InvocationRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    forEachRow(n, pool, bindings.x86_v3, kernel_, [](K& k, int y, int z, int x0, int x1) {
      glsl::Invocation inv;
      for (int x = x0; x < x1; ++x) runInvocation(k, inv, x, y, z);
    });
  }

 private:
  KernelSlots slots_;
  K kernel_{&slots_};
};

template <class KU>
using UncheckedRunner = InvocationRunner<KU>;

// UncheckedRunner for a row stage (fluid/row_reduction.h: LOCAL_SIZE(ROW_X, ROW_Y, 1), one
// invocation per row of u_res.x cells, the row's sum in order into partials[]): the same, but
// the serial threshold counts cells, so the seed grid's 7000 rows of 100 cells run on every
// thread (counted as invocations they ran on one). The partials do not depend on the split.
template <class KU>
class RowLoopRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    forEachRow(
        n, pool, bindings.x86_v3, kernel_,
        [](KU& k, int y, int z, int x0, int x1) {
          glsl::Invocation inv;
          for (int x = x0; x < x1; ++x) runInvocation(k, inv, x, y, z);
        },
        std::max(1, kernel_.u_res.x));
  }

 private:
  KernelSlots slots_;
  KU kernel_{&slots_};
};

// The same main() built twice from the shader: K bounds-tested, KU (glsl::UncheckedImage) not.
// Invocations at least one from every face of the dispatch box run KU, the shell around them K:
// for a kernel whose accesses reach at most one cell (or face) from its invocation's (a
// stencil), every access of the interior is in range. A kernel file that uses it says so.
template <class K, class KU>
class InteriorRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    forRows(
        n, pool,
        [&](int y, int z) {
          runBest(bindings.x86_v3, [&] {
            K k(checked_);
            glsl::Invocation inv;
            if (y == 0 || z == 0 || y == n.y - 1 || z == n.z - 1 || n.x < 3) {
              for (int x = 0; x < n.x; ++x) runInvocation(k, inv, x, y, z);
              return;
            }
            KU ku(unchecked_);
            runInvocation(k, inv, 0, y, z);
            for (int x = 1; x < n.x - 1; ++x) runInvocation(ku, inv, x, y, z);
            runInvocation(k, inv, n.x - 1, y, z);
          });
        },
        [&](int x0, int x1) {
          runBest(bindings.x86_v3, [&] {
            K k(checked_);
            glsl::Invocation inv;
            for (int x = x0; x < x1; ++x) runInvocation(k, inv, x, 0, 0);
          });
        });
  }

 private:
  KernelSlots slots_;  // both builds register here: binding and uniforms reach both
  K checked_{&slots_};
  KU unchecked_{&slots_};
};

// A kernel file's row loop for a stage whose shader exposes its per-invocation arithmetic as a
// branch-free function (the vectorizable part): Body::box(kernel, n) gives the invocations that
// do work (the dispatch box clipped to the stage's grid), and Body()(k, x, y, z) computes and
// stores one, called under `omp simd` on a per-thread copy of the unchecked build KU. The kernel
// file says why the box's accesses are in range.
// A stage dispatched once per axis (uniform u_axis 0, 1 or 2) may have its row loops compiled
// once per axis: with Body::kPerAxis true, the runner sets the per-thread kernel copy's u_axis to
// the constant it holds before the loop, so the shader's component(v, u_axis), unitAxis(u_axis)
// and the like fold away (the copy is a local: the compiler forwards the constant) and a face
// image's one channel is loaded instead of four. One source: the shader still reads u_axis.
template <class Body, class = void>
struct PerAxis : std::false_type {};
template <class Body>
struct PerAxis<Body, std::void_t<decltype(Body::kPerAxis)>> : std::bool_constant<Body::kPerAxis> {};

// loop() with the u_axis of every kernel copy in `ks` (builds of one stage: the same uniform)
// set to the constant it holds.
template <class Loop, class K, class... More>
__attribute__((always_inline)) inline void withAxisFolded(const Loop& loop, K& k, More&... more) {
  switch (k.u_axis) {
    case 0: k.u_axis = 0, ((more.u_axis = 0), ...); loop(); return;
    case 1: k.u_axis = 1, ((more.u_axis = 1), ...); loop(); return;
    case 2: k.u_axis = 2, ((more.u_axis = 2), ...); loop(); return;
    default: loop(); return;
  }
}

template <class KU, class Body>
class SimdRowRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 box = Body::box(kernel_, n);
    if (box.x <= 0 || box.y <= 0 || box.z <= 0) return;
    forEachRow(box, pool, bindings.x86_v3, kernel_, [](KU& k, int y, int z, int x0, int x1) {
      const Body body;
      auto loop = [&] {
        HF_OMP_SIMD
        for (int x = x0; x < x1; ++x) body(k, x, y, z);
      };
      if constexpr (PerAxis<Body>::value) {
        withAxisFolded(loop, k);
      } else {
        loop();
      }
    });
  }

 private:
  KernelSlots slots_;
  KU kernel_{&slots_};
};

// SimdRowRunner for a stage whose lookups are clamped to the grid (clampCell) and reach at most one
// cell from the invocation's: KI is the same shader built with HF_CLAMP_FREE (clampCell the
// identity), run on the cells 1 .. res - 2 of every axis (u_res), where every neighbour is in the
// grid and the clamp changes nothing, so the same bits; the other cells run KU. The clamp per lane
// made the row's loads gathers; without it they are contiguous.
template <class KU, class KI, class Body>
class InteriorSimdRowRunner final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 box = Body::box(clamped_, n);
    if (box.x <= 0 || box.y <= 0 || box.z <= 0) return;
    const glm::ivec3 res = clamped_.u_res;
    forRows(
        box, pool,
        [&](int y, int z) {
          runBest(bindings.x86_v3, [&] {
            KU k(clamped_);
            KI ki(free_);
            const Body body;
            const bool inner_row = y >= 1 && y <= res.y - 2 && z >= 1 && z <= res.z - 2;
            const int lo = inner_row ? std::min(1, box.x) : box.x;
            const int hi = inner_row ? std::max(lo, std::min(box.x, res.x - 1)) : box.x;
            auto loops = [&] {
              for (int x = 0; x < lo; ++x) body(k, x, y, z);
              HF_OMP_SIMD
              for (int x = lo; x < hi; ++x) body(ki, x, y, z);
              HF_OMP_SIMD
              for (int x = hi; x < box.x; ++x) body(k, x, y, z);
            };
            if constexpr (PerAxis<Body>::value) {
              withAxisFolded(loops, k, ki);
            } else {
              loops();
            }
          });
        },
        [&](int x0, int x1) {
          runBest(bindings.x86_v3, [&] {
            KU k(clamped_);
            const Body body;
            for (int x = x0; x < x1; ++x) body(k, x, 0, 0);
          });
        },
        1);
  }

 private:
  KernelSlots slots_;  // both builds register here: binding and uniforms reach both
  KU clamped_{&slots_};
  KI free_{&slots_};
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
  auto groupRange = [&](int begin, int end) {
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
  };
  const long long invocations = static_cast<long long>(count) * local.x * local.y * local.z;
  if (invocations < kSerialInvocations) {
    groupRange(0, count);
  } else {
    pool.parallelFor(count, groupRange);
  }
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
