// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/dispatch_floor.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "common/error.h"
#include "compute/compute_program.h"
#include "compute/texture3d.h"
#include "compute/workgroup.h"
#include "gl/gl_check.h"

namespace hf::gl {
using namespace compute;  // Texture3D, ComputeProgram, ... (this benchmark runs only on a GL device)
namespace {

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Timing {
  double wall_s = 0.0;
  double cpu_s = 0.0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One untimed dispatch (compilation and first-use costs), then `repeats` timed ones, each
// followed by glFinish so its wall time covers its execution: the medians of each.
Timing timeDispatches(ComputeProgram& program, Texture3D& out, const glm::ivec3& cells, int repeats) {
  program.set("u_res", cells);
  out.bindImage(0, Access::Write);
  program.dispatch(cells);
  glFinish();
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = processCpuSeconds();
    program.dispatch(cells);
    glFinish();
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    cpu.push_back(processCpuSeconds() - cpu0);
  }
  checkGl("dispatch floor");
  return {median(wall), median(cpu)};
}

}  // namespace

DispatchFloor measureDispatchFloor(const glm::ivec3& cells, int repeats) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max_size);
  for (int a = 0; a < 3; ++a) {
    if (cells[a] < 1 || cells[a] > max_size) {
      throw InvalidArgument("resolution: each cell count must be 1.." + std::to_string(max_size) +
                            " (this device's largest 3D texture), got " + std::to_string(cells[a]));
    }
  }
  if (repeats < 1) throw InvalidArgument("repeats: must be >= 1, got " + std::to_string(repeats));

  Texture3D out(cells, TexelFormat::R32F, "dispatch floor output");
  ComputeProgram empty("dispatch_floor.comp", cellGroupDefines());
  Defines store_defines = cellGroupDefines();
  store_defines.emplace_back("STORE", "1");
  ComputeProgram store("dispatch_floor.comp", store_defines);

  DispatchFloor f;
  f.cells = cells;
  f.repeats = repeats;
  f.launched = static_cast<double>(groupCount(cells)) * kCellGroup.x * kCellGroup.y * kCellGroup.z;
  const double per = 1e9 / f.launched;
  const Timing e = timeDispatches(empty, out, cells, repeats);
  const Timing s = timeDispatches(store, out, cells, repeats);
  f.empty_wall_ns = e.wall_s * per;
  f.empty_cpu_ns = e.cpu_s * per;
  f.store_wall_ns = s.wall_s * per;
  f.store_cpu_ns = s.cpu_s * per;
  return f;
}

}  // namespace hf::gl
