// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/kernel.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "common/error.h"

namespace hf::cpu {
namespace {

// #defines that only shape the GPU's workgroups.
bool isShapeDefine(const std::string& name) {
  for (const char* n : {"WG_X", "WG_Y", "WG_Z", "ROW_X", "ROW_Y", "WG_LINEAR", "REDUCE_SIZE", "COARSEST"}) {
    if (name == n) return true;
  }
  return false;
}

compute::Defines variantKey(compute::Defines defines) {
  defines.erase(std::remove_if(defines.begin(), defines.end(), [](const auto& d) { return isShapeDefine(d.first); }),
                defines.end());
  std::sort(defines.begin(), defines.end());
  return defines;
}

std::string definesText(const compute::Defines& defines) {
  std::string s;
  for (const auto& [name, value] : defines) s += (s.empty() ? "" : ", ") + name + "=" + value;
  return s.empty() ? "no #defines" : s;
}

int defineValue(const compute::Defines& defines, const char* name, int fallback) {
  for (const auto& [n, v] : defines) {
    if (n == name) return std::stoi(v);
  }
  return fallback;
}

bool detectX86V3() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (const char* env = std::getenv(kCpuIsaEnv); env != nullptr && std::strcmp(env, "baseline") == 0) return false;
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
         __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("f16c") && __builtin_cpu_supports("lzcnt") &&
         __builtin_cpu_supports("movbe") && __builtin_cpu_supports("popcnt");
#else
  return false;
#endif
}

}  // namespace

bool cpuHasX86V3() {
  static const bool v3 = detectX86V3();
  return v3;
}

namespace glsl {
void barrierUnavailable() {
  throw std::logic_error("a kernel with workgroup barriers ran through the per-invocation runner");
}
}  // namespace glsl

void storeGroupSums(const glsl::GroupSums& sums, unsigned group, unsigned groups, const BufferBinding& partials) {
  auto* out = static_cast<glm::vec4*>(partials.data);
  const std::size_t length = partials.bytes / sizeof(glm::vec4);
  for (unsigned part = 0; part < sums.parts; ++part) {
    const std::size_t i = static_cast<std::size_t>(part) * groups + group;
    if (out != nullptr && i < length) out[i] = sums.sums[part];  // GL drops a write past the buffer too
  }
}

void KernelRegistry::addEntry(const std::string& file, compute::Defines defines,
                              std::function<std::unique_ptr<CpuKernel>()> make) {
  entries_.push_back({file, variantKey(std::move(defines)), std::move(make)});
}

std::unique_ptr<CpuKernel> KernelRegistry::make(const std::string& file, const compute::Defines& defines) const {
  const compute::Defines key = variantKey(defines);
  for (const KernelEntry& e : entries_) {
    if (e.file == file && e.defines == key) return e.make();
  }
  throw Error("the CPU backend has no kernel '" + file + "' with " + definesText(key) +
              " (a stage added to shaders/ needs its C++ build in cpp/cpu/kernels/)");
}

glm::ivec3 localSizeOf(const compute::Defines& d) {
  if (defineValue(d, "WG_X", 0) > 0) {
    return {defineValue(d, "WG_X", 1), defineValue(d, "WG_Y", 1), defineValue(d, "WG_Z", 1)};
  }
  if (defineValue(d, "ROW_X", 0) > 0) return {defineValue(d, "ROW_X", 1), defineValue(d, "ROW_Y", 1), 1};
  if (defineValue(d, "WG_LINEAR", 0) > 0) return {defineValue(d, "WG_LINEAR", 1), 1, 1};
  if (defineValue(d, "REDUCE_SIZE", 0) > 0) return {defineValue(d, "REDUCE_SIZE", 1), 1, 1};
  const int c = defineValue(d, "COARSEST", 0);
  if (c > 0) return {c, c, c};
  return {1, 1, 1};
}

}  // namespace hf::cpu
