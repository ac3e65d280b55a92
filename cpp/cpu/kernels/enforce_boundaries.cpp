// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/enforce_boundaries.comp built as C++ (cpu/kernel.h).
// Its accesses reach at most one cell or face from its invocation's (coarse-to-fine stages: the
// children of its cell and their neighbours), so the interior of the dispatch runs unchecked
// and the shell around it bounds-tested (EnforceRows below, which also passes by the faces the
// shader leaves at once).
#include "cpu/kernels/kernel_list.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EnforceBoundaries : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};

#undef HF_IMAGE
#define HF_IMAGE ::hf::cpu::glsl::UncheckedImage

struct EnforceBoundariesUnchecked : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};

}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {

namespace {

// InteriorRunner's split (the shell bounds-tested, the interior unchecked), with the faces the
// shader leaves at once passed by: a face inside the grid (not index 0 or u_res along u_axis) with
// an open fraction above 0 returns before any write, and most faces are such. Testing that here is
// one load and a compare instead of the invocation (2.8 % of a seed-grid step on one thread went
// to those early returns); every other face runs the shader as before.
class EnforceRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const int axis = checked_.u_axis;
    const glm::ivec3 res = checked_.u_res;
    const ImageBinding& faces = checked_.u_face_open;
    const bool can_skip = axis >= 0 && axis <= 2 && faces.data != nullptr && faces.size == res + 1;
    const float* open = can_skip ? static_cast<const float*>(faces.data) + static_cast<std::size_t>(axis) * faces.plane
                                 : nullptr;
    const glm::ivec3 face_size = res + glm::ivec3(axis == 0, axis == 1, axis == 2);
    auto skip = [&](const glm::ivec3& c) {
      if (!can_skip || glm::any(glm::greaterThanEqual(c, face_size))) return false;
      const int i = c[axis];
      return i != 0 && i != res[axis] && open[c.x + faces.stride_y * c.y + faces.stride_z * c.z] > 0.0f;
    };
    forRows(
        n, pool,
        [&](int y, int z) {
          runBest(bindings.x86_v3, [&] {
            EnforceBoundaries k(checked_);
            EnforceBoundariesUnchecked ku(unchecked_);
            glsl::Invocation inv;
            const bool shell = y == 0 || z == 0 || y == n.y - 1 || z == n.z - 1 || n.x < 3;
            for (int x = 0; x < n.x; ++x) {
              if (skip(glm::ivec3(x, y, z))) continue;
              if (shell || x == 0 || x == n.x - 1) {
                runInvocation(k, inv, x, y, z);
              } else {
                runInvocation(ku, inv, x, y, z);
              }
            }
          });
        },
        [&](int x0, int x1) {
          runBest(bindings.x86_v3, [&] {
            EnforceBoundaries k(checked_);
            glsl::Invocation inv;
            for (int x = x0; x < x1; ++x) runInvocation(k, inv, x, 0, 0);
          });
        });
  }

 private:
  KernelSlots slots_;  // both builds register here: binding and uniforms reach both
  EnforceBoundaries checked_{&slots_};
  EnforceBoundariesUnchecked unchecked_{&slots_};
};

}  // namespace

void addEnforceBoundaries(KernelRegistry& r) {
  r.add<EnforceRows>("enforce_boundaries.comp", {});
}

}  // namespace hf::cpu::kernels
