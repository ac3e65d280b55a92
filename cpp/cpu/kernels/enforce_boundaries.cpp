// SPDX-License-Identifier: GPL-3.0-or-later
// shaders/enforce_boundaries.comp built as C++ (cpu/kernel.h), with a row loop of its own.
// The shader stores only on the domain's walls and on faces whose open fraction is not above 0
// (wholly covered); for every other face main() returns after loading the fraction. Those are
// nearly all faces (the stage ran 4 % of a one-thread seed step calling main() for each), so the
// loop tests the axis's fraction plane 16 faces at a time (vectorized) and calls the shader's main()
// only for the faces of a block that has a covered one, and for every wall face: main() then
// decides, as on the GPU. That main() is the bounds-tested build: it runs for few faces.
#include "cpu/kernels/kernel_list.h"

#include <algorithm>
#include <string>

#include "common/error.h"

#include "cpu/kernel_begin.h"
namespace hf::cpu::kernels {
namespace {
using namespace ::hf::cpu::glsl;

struct EnforceBoundaries : KernelBase {
  using KernelBase::KernelBase;
#include "common.glsl"
#include "enforce_boundaries.comp"
};


}  // namespace
}  // namespace hf::cpu::kernels
#include "cpu/kernel_end.h"

namespace hf::cpu::kernels {
namespace {

constexpr int kBlock = 16;  // faces tested together

class BoundaryRows final : public CpuKernel {
 public:
  KernelSlots& slots() override { return slots_; }
  void run(const glm::ivec3& n, const glm::ivec3&, const Bindings& bindings, ThreadPool& pool) override {
    const int axis = kernel_.u_axis;
    if (axis < 0 || axis > 2) throw Error("enforce_boundaries: u_axis must be 0, 1 or 2, got " + std::to_string(axis));
    const glm::ivec3 res = kernel_.u_res;
    const glm::ivec3 faces = glm::min(n, kernel_.faceSize(axis));  // the dispatch within the shader's bounds test
    if (faces.x <= 0 || faces.y <= 0 || faces.z <= 0) return;
    const ImageBinding& open = kernel_.u_face_open;
    if (open.data == nullptr || glm::any(glm::lessThan(open.size, faces))) {
      throw Error("enforce_boundaries: the face fractions are not bound over the axis's faces");
    }
    const float* plane = static_cast<const float*>(open.data) + open.plane * static_cast<std::size_t>(axis);
    forEachRow(faces, pool, bindings.x86_v3, kernel_, [&](EnforceBoundaries& k, int y, int z, int x0, int x1) {
      glsl::Invocation inv;
      if ((axis == 1 && (y == 0 || y == res.y)) || (axis == 2 && (z == 0 || z == res.z))) {  // a wall's row
        for (int x = x0; x < x1; ++x) runInvocation(k, inv, x, y, z);
        return;
      }
      int lo = x0, hi = x1;
      if (axis == 0) {  // the row's two wall faces
        for (int x : {0, res.x}) {
          if (x0 <= x && x < x1) runInvocation(k, inv, x, y, z);
        }
        lo = std::max(x0, 1);
        hi = std::min(x1, res.x);
      }
      const float* fraction = plane + static_cast<std::ptrdiff_t>(y) * open.stride_y +
                              static_cast<std::ptrdiff_t>(z) * open.stride_z;
      for (int b0 = lo; b0 < hi; b0 += kBlock) {
        const int b1 = std::min(hi, b0 + kBlock);
        unsigned covered = 0;
#pragma omp simd reduction(|: covered)
        for (int x = b0; x < b1; ++x) covered |= fraction[x] > 0.0f ? 0u : 1u;
        if (covered == 0) continue;
        for (int x = b0; x < b1; ++x) {
          if (!(fraction[x] > 0.0f)) runInvocation(k, inv, x, y, z);
        }
      }
    });
  }

 private:
  KernelSlots slots_;
  EnforceBoundaries kernel_{&slots_};
};

}  // namespace

void addEnforceBoundaries(KernelRegistry& r) {
  r.add<BoundaryRows>("enforce_boundaries.comp", {});
}

}  // namespace hf::cpu::kernels
