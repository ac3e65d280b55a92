// SPDX-License-Identifier: GPL-3.0-or-later
#include "cpu/kernel.h"

#include <algorithm>
#if defined(__x86_64__)
#include <cpuid.h>
#endif
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

// The CPU's x86-64-v3 features from CPUID (not __builtin_cpu_supports: its data lives in the
// compiler's runtime, which the wheel's static, position-independent build cannot link), and
// whether the OS saves the AVX registers (XGETBV).
bool detectX86V3() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (const char* env = std::getenv(kCpuIsaEnv); env != nullptr && std::strcmp(env, "baseline") == 0) return false;
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
  const bool fma = (c >> 12) & 1u, movbe = (c >> 22) & 1u, popcnt = (c >> 23) & 1u, osxsave = (c >> 27) & 1u,
             avx = (c >> 28) & 1u, f16c = (c >> 29) & 1u;
  if (!(fma && movbe && popcnt && osxsave && avx && f16c)) return false;
  unsigned xcr0_lo = 0, xcr0_hi = 0;
  __asm__ volatile("xgetbv" : "=a"(xcr0_lo), "=d"(xcr0_hi) : "c"(0));
  if ((xcr0_lo & 0x6u) != 0x6u) return false;  // the OS saves XMM and YMM state
  if (!__get_cpuid_count(7, 0, &a, &b, &c, &d)) return false;
  const bool bmi1 = (b >> 3) & 1u, avx2 = (b >> 5) & 1u, bmi2 = (b >> 8) & 1u;
  if (!__get_cpuid(0x80000001u, &a, &b, &c, &d)) return false;
  const bool lzcnt = (c >> 5) & 1u;
  return avx2 && bmi1 && bmi2 && lzcnt;
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
