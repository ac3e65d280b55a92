// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/mg_smooth.comp built as C++ (cpu/kernel.h), with a row loop of its own: the smoothing
// sweeps are most of a multigrid solve. The loop walks one row of cells of the sweep's colour,
// loads each cell's neighbourhood from the arrays and calls the shader's smoothedValue, the
// per-cell arithmetic the GPU runs too (the same bits). Loads past the grid's edge land in the
// textures' guard bands and are not used (the cell has no link there), so no bounds tests.
// A row whose inner cells (1 .. nx - 2) are all fluid with six links and six wholly open faces (most
// rows away from the walls and the probe) calls smoothedValue with that mask and those fractions
// as constants (cpu/regular_rows.h), so the mask's bit tests fold away and neither mask nor faces
// is read for them (nor for its end cells where they are against a wall on x). With w = 1 the
// shader's sums are the same bits (1 * x is x; n adds six 1s).
// The sweeps of one level dispatched as a series (MultigridVCycle::sweepSeries: red, black, ...)
// run in one pass over the level, each a plane behind the one before (SmoothSweep::runSeries).
#include "cpu/kernels/kernel_list.h"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/error.h"
#include "cpu/regular_rows.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct MgSmooth : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef NEIGHBOUR_X  // the shader defines it per variant

#define PROLONG 1
struct MgSmoothProlong : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "mg_smooth.comp"
};
#undef PROLONG
#undef NEIGHBOUR_X

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

template <class T>
T* texels(const ImageBinding& image) {
  return static_cast<T*>(image.data);
}

void checkSize(const ImageBinding& image, const glm::ivec3& want, const char* name) {
  if (image.data == nullptr || image.size != want) {
    throw Error(std::string("mg_smooth: image ") + name + " is not bound at the level's size");
  }
}

// One sweep of either build (plain or PROLONG), as the fused pair sees it: its level's images,
// colour and rows.
class SmoothSweep : public CpuKernel {
 public:
  void run(const glm::ivec3&, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    prepare(bindings, pool);
    const glm::ivec3 n = res();
    forRows(n, pool, [&](int y, int z) { rows(z, y, y + 1, bindings.x86_v3); }, [](int, int) {});
  }

  // A series of sweeps of one level, their colours alternating (MultigridVCycle's
  // dispatchSeries: the smoothing before or after a coarse correction), in one pass over the
  // level: sweep j's plane z - j right after sweep j - 1's plane z - j + 1, so each sweep reads the
  // planes the sweep before just wrote from the cache instead of another pass over memory. Each
  // cell's update reads the same values as in separate passes (sweep j's plane p reads the other
  // colour's planes p - 1 .. p + 1, which sweep j - 1 has written, since it runs a plane ahead,
  // and sweep j + 1 has not, since it runs a plane behind), so the result has the same bits. On
  // several threads the grid is cut into slabs of planes, one a thread; sweep j's planes within j
  // of an edge between slabs read (through sweep j - 1's) the other slab's planes, so they run
  // after the slabs, sweep by sweep (short parallel passes over the edges' planes).
  bool runSeries(const std::vector<CpuKernel*>& series, const Bindings& bindings, ThreadPool& pool) override {
    std::vector<SmoothSweep*> sweeps;
    for (CpuKernel* k : series) {
      auto* sweep = dynamic_cast<SmoothSweep*>(k);
      if (sweep == nullptr || !sameLevel(*sweep) || sweep->colour() != (colour() + static_cast<int>(sweeps.size())) % 2) {
        return false;
      }
      sweeps.push_back(sweep);
    }
    for (SmoothSweep* sweep : sweeps) sweep->prepare(bindings, pool);
    const int m = static_cast<int>(sweeps.size());
    const glm::ivec3 n = res();
    const bool v3 = bindings.x86_v3;
    const long long cells = static_cast<long long>(n.x) * n.y * n.z;
    // Slabs of at least 2 m planes: the deferred planes (m (m - 1) a pair of slabs) are then at
    // most a quarter of the series (with 4 m, the seed grid's second level, 35 planes, ran its six
    // sweeps on one thread: 0.7-1.4 ms more a solve).
    const int slabs = (cells >= kSlabbedCells && n.z >= 2 * m * pool.threads()) ? pool.threads() : 1;
    auto slabStart = [&](int slab) { return static_cast<int>(static_cast<long long>(n.z) * slab / slabs); };
    // Sweep j's planes of slab [z0, z1) that read another slab's planes: within j of an inner edge.
    auto deferred = [&](int j, int plane, int z0, int z1) {
      return (z0 > 0 && plane < z0 + j) || (z1 < n.z && plane >= z1 - j);
    };
    pool.parallelFor(slabs, [&](int s0, int s1) {
      for (int slab = s0; slab < s1; ++slab) {
        const int z0 = slabStart(slab), z1 = slabStart(slab + 1);
        for (int t = z0; t < z1 + m - 1; ++t) {
          for (int j = 0; j < m; ++j) {
            const int plane = t - j;
            if (plane >= z0 && plane < z1 && !deferred(j, plane, z0, z1)) sweeps[static_cast<std::size_t>(j)]->rows(plane, 0, n.y, v3);
          }
        }
      }
    });
    for (int j = 1; j < m && slabs > 1; ++j) {
      std::vector<int> planes;
      for (int slab = 0; slab < slabs; ++slab) {
        const int z0 = slabStart(slab), z1 = slabStart(slab + 1);
        for (int plane = z0; plane < z1; ++plane) {
          if (deferred(j, plane, z0, z1)) planes.push_back(plane);
        }
      }
      const SmoothSweep* sweep = sweeps[static_cast<std::size_t>(j)];
      const int count = static_cast<int>(planes.size()) * n.y;
      pool.parallelFor(count, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) sweep->rows(planes[static_cast<std::size_t>(i / n.y)], i % n.y, i % n.y + 1, v3);
      });
    }
    return true;
  }

 protected:
  // Below this many cells a level's series runs on one thread, as any other small dispatch
  // (kSerialInvocations: the slabs' hand-over and the idle workers' spinning cost more).
  static constexpr long long kSlabbedCells = kSerialInvocations;

  // Checks the bindings and finds the open rows; then rows() may run.
  virtual void prepare(const Bindings& bindings, ThreadPool& pool) = 0;
  // Rows y0 .. y1 - 1 of plane z, with the best instruction set.
  virtual void rows(int z, int y0, int y1, bool x86_v3) const = 0;
  virtual glm::ivec3 res() const = 0;
  virtual int colour() const = 0;
  // The level's images: x, b, mask, faces.
  virtual std::array<const void*, 4> images() const = 0;

 private:
  bool sameLevel(const SmoothSweep& other) const { return res() == other.res() && images() == other.images(); }
};

template <class K, bool kProlong>
class SmoothRows final : public SmoothSweep {
 public:
  KernelSlots& slots() override { return slots_; }

 protected:
  void prepare(const Bindings& bindings, ThreadPool& pool) override {
    const glm::ivec3 res = kernel_.u_res;
    checkSize(kernel_.u_x, res, "x");
    checkSize(kernel_.u_b, res, "b");
    checkSize(kernel_.u_mask, res, "mask");
    checkSize(kernel_.u_faces, res + 1, "faces");
    coarse_ = glm::ivec3(0);
    if constexpr (kProlong) {
      coarse_ = kernel_.u_coarse_x.size;
      if (kernel_.u_coarse_x.data == nullptr || glm::any(glm::lessThan(coarse_ * 2, res))) {
        throw Error("mg_smooth: the coarse x is not bound at the next level's size");
      }
    }
    regular_ = bindings.regular_rows->flags(kernel_.u_mask, kernel_.u_faces, res, pool, bindings.x86_v3);
  }

  void rows(int z, int y0, int y1, bool x86_v3) const override {
    const glm::ivec3 res = kernel_.u_res;
    runBest(x86_v3, [&] {
      K k(kernel_);  // one copy for the rows (a coarse level's rows are a few cells)
      for (int y = y0; y < y1; ++y) row(k, y, z, res, coarse_, regular_[y + z * res.y]);
    });
  }

  glm::ivec3 res() const override { return kernel_.u_res; }
  int colour() const override { return kernel_.u_colour & 1; }
  std::array<const void*, 4> images() const override {
    return {kernel_.u_x.data, kernel_.u_b.data, kernel_.u_mask.data, kernel_.u_faces.data};
  }

 private:
  // Only this colour's cells of the row are computed: every second cell, by a loop over j that
  // GCC vectorizes with stride-2 loads (two vector loads and a permute per operand; the stores go
  // lane by lane). They are written in place: a cell of this colour reads only the other colour's
  // cells (its x neighbours in the row, its y and z neighbours at the same i), which this sweep
  // does not write, so the order of the writes does not matter. (Storing each result with the
  // unchanged cell after it, one contiguous store a pair, cost more: the next lanes' loads of
  // those cells waited on the stores, 27 % of a one-thread 48^3 step against 20 %.)
  // (always_inline: flattened into each instruction set's build by runBest.)
  __attribute__((always_inline)) static void row(K& k, int y, int z, const glm::ivec3& res, const glm::ivec3& coarse,
                                                 std::uint8_t shape) {
    float* x = texels<float>(k.u_x);
    const float* __restrict b = texels<float>(k.u_b);
    const std::uint8_t* __restrict mask = texels<std::uint8_t>(k.u_mask);
    const std::size_t plane = k.u_faces.plane;
    const float* __restrict fx = texels<float>(k.u_faces);
    const float* __restrict fy_ = fx + plane;
    const float* __restrict fz_ = fx + 2 * plane;
    const int sy = res.x, sz = res.x * res.y;
    const int fy = res.x + 1, fz = (res.x + 1) * (res.y + 1);
    const int row = y * sy + z * sz, frow = y * fy + z * fz;
    const int first = (y + z + k.u_colour) & 1;  // this sweep's cells: i = first, first + 2, ...
    const float* __restrict xr = x;  // read: the other colour's cells only
    float* __restrict xw = x + row;  // written: this colour's cells of the row only
    // Cells i = from, from + 2, ... up to `to` (inclusive) of this colour: their count.
    auto count = [](int from, int to) { return from <= to ? (to - from) / 2 + 1 : 0; };
    // A regular row: its inner cells with the mask and fractions as constants, its end cells too
    // where they are against a wall on x (wallLinks: so a regular row reads neither, whose cache
    // lines no other cell reads), else as any.
    const glm::vec3 open(1.0f);
    const bool regular = (shape & kOpenInside) != 0;
    const int inner0 = first == 0 ? 2 : 1;  // the first inner cell (1 .. res.x - 2) of this colour
    auto isMine = [&](int i) { return ((i - first) & 1) == 0; };
    if constexpr (!kProlong) {
      auto general = [&](int i) {
        const int c = row + i, f = frow + i;
        return k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]), glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                               glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]), glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]),
                               b[c]);
      };
      if (regular) {
        const int n = count(inner0, res.x - 2);
#pragma omp simd
        for (int j = 0; j < n; ++j) {
          const int i = inner0 + 2 * j, c = row + i;
          xw[i] = k.smoothedValue(kAllLinks, open, open, glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]),
                                  glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]), b[c]);
        }
        for (int i : {0, res.x - 1}) {
          if (!isMine(i)) continue;
          const std::uint32_t links = wallLinks(shape, i, res.x);
          const int c = row + i;
          xw[i] = links != 0u ? k.smoothedValue(links, open, open, glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]),
                                                glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]), b[c])
                              : general(i);
        }
      } else {
        const int n = count(first, res.x - 1);
#pragma omp simd
        for (int j = 0; j < n; ++j) {
          const int i = first + 2 * j, c = row + i, f = frow + i;
          xw[i] = k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]),
                                  glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                                  glm::vec3(xr[c - 1], xr[c - sy], xr[c - sz]),
                                  glm::vec3(xr[c + 1], xr[c + sy], xr[c + sz]), b[c]);
        }
      }
    } else {
      // x + the coarse level's x of the neighbour's parent: mg_prolong folded into the sweep. For
      // the cells i = from + 2 j of this colour the parents of their neighbours are consecutive
      // coarse cells, j on: (i - 1) / 2 and (i + 1) / 2 along the row, i / 2 in the rows beside
      // (from 1 or 2; C's and GLSL's division, so cell -1's parent is 0, where a row starting at
      // cell 0 takes that cell alone). So the loop loads them whole from the coarse rows.
      const float* cx = texels<float>(k.u_coarse_x);
      const int csy = coarse.x, csz = coarse.x * coarse.y;
      const float* mid = cx + (y / 2) * csy + (z / 2) * csz;  // this row's parents
      const float* ylo = cx + ((y - 1) / 2) * csy + (z / 2) * csz;
      const float* yhi = cx + ((y + 1) / 2) * csy + (z / 2) * csz;
      const float* zlo = cx + (y / 2) * csy + ((z - 1) / 2) * csz;
      const float* zhi = cx + (y / 2) * csy + ((z + 1) / 2) * csz;
      auto parent = [](const float* coarse_row, int i) { return coarse_row[i / 2]; };  // i >= -1
      auto general = [&](int i) {
        const int c = row + i, f = frow + i;
        return k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]), glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                               glm::vec3(xr[c - 1] + parent(mid, i - 1), xr[c - sy] + parent(ylo, i),
                                         xr[c - sz] + parent(zlo, i)),
                               glm::vec3(xr[c + 1] + parent(mid, i + 1), xr[c + sy] + parent(yhi, i),
                                         xr[c + sz] + parent(zhi, i)),
                               b[c]);
      };
      // Cells i = from, from + 2, ... up to `to` of this colour (from 1 or 2), each cell's value by
      // cell(i, c, lo, hi) from its neighbours' x plus their parents' (loaded whole, j on).
      auto run = [&](int from, int to, auto&& cell) {
        const int n = count(from, to);
        const float* __restrict pxl = mid + (from - 1) / 2;
        const float* __restrict pxh = mid + (from + 1) / 2;
        const float* __restrict pyl = ylo + from / 2;
        const float* __restrict pyh = yhi + from / 2;
        const float* __restrict pzl = zlo + from / 2;
        const float* __restrict pzh = zhi + from / 2;
#pragma omp simd
        for (int j = 0; j < n; ++j) {
          const int i = from + 2 * j, c = row + i;
          xw[i] = cell(i, c, glm::vec3(xr[c - 1] + pxl[j], xr[c - sy] + pyl[j], xr[c - sz] + pzl[j]),
                       glm::vec3(xr[c + 1] + pxh[j], xr[c + sy] + pyh[j], xr[c + sz] + pzh[j]));
        }
      };
      if (regular) {
        run(inner0, res.x - 2, [&](int, int c, const glm::vec3& lo, const glm::vec3& hi) {
          return k.smoothedValue(kAllLinks, open, open, lo, hi, b[c]);
        });
        for (int i : {0, res.x - 1}) {
          if (!isMine(i)) continue;
          const std::uint32_t links = wallLinks(shape, i, res.x);
          const int c = row + i;
          xw[i] = links != 0u ? k.smoothedValue(links, open, open,
                                                glm::vec3(xr[c - 1] + parent(mid, i - 1), xr[c - sy] + parent(ylo, i),
                                                          xr[c - sz] + parent(zlo, i)),
                                                glm::vec3(xr[c + 1] + parent(mid, i + 1), xr[c + sy] + parent(yhi, i),
                                                          xr[c + sz] + parent(zhi, i)),
                                                b[c])
                              : general(i);
        }
      } else {
        if (first == 0) xw[0] = general(0);
        run(first == 0 ? 2 : 1, res.x - 1, [&](int i, int c, const glm::vec3& lo, const glm::vec3& hi) {
          const int f = frow + i;
          return k.smoothedValue(mask[c], glm::vec3(fx[f], fy_[f], fz_[f]), glm::vec3(fx[f + 1], fy_[f + fy], fz_[f + fz]),
                                 lo, hi, b[c]);
        });
      }
    }
  }

  KernelSlots slots_;
  K kernel_{&slots_};
  glm::ivec3 coarse_{0};
  const std::uint8_t* regular_ = nullptr;
};

}  // namespace

void addMgSmooth(KernelRegistry& r) {
  r.add<SmoothRows<MgSmooth, false>>("mg_smooth.comp", {});
  r.add<SmoothRows<MgSmoothProlong, true>>("mg_smooth.comp", {{"PROLONG", "1"}});
}

}  // namespace hf::cpu::kernels
