// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// Numbers in error messages: shortest round-trip-ish form ("1e-40", "0.5"), never "0.000000".
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

namespace hf {

inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.7g", v);
  return buf;
}

// Three significant digits, for figures a person reads in a status line ("0.0307 kg").
inline std::string num3(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

inline std::string vecText(const glm::vec3& v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }
inline std::string ivecText(const glm::ivec3& v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

}  // namespace hf
