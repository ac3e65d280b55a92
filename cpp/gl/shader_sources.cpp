// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/shader_sources.h"

#include <map>

#include "common/error.h"

namespace hf::gl {

const std::string& shaderSource(const std::string& file) {
  static const std::map<std::string, std::string> by_name = [] {
    std::map<std::string, std::string> m;
    for (const auto& s : embeddedShaders()) m.emplace(s.file, s.source);
    return m;
  }();
  auto it = by_name.find(file);
  if (it == by_name.end()) throw Error("shader '" + file + "' is not embedded in this build");
  return it->second;
}

}  // namespace hf::gl
