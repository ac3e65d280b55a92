// SPDX-License-Identifier: GPL-3.0-or-later
#include "gl/gl_stage_timer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>

#include "gl/gl_check.h"

namespace hf::gl {


GlStageTimer::~GlStageTimer() {
  if (!pool_.empty()) glDeleteQueries(static_cast<GLsizei>(pool_.size()), pool_.data());
}

unsigned int GlStageTimer::query(std::size_t i) {
  while (pool_.size() <= i) {
    GLuint q = 0;
    glGenQueries(1, &q);
    pool_.push_back(q);
  }
  return pool_[i];
}

void GlStageTimer::begin() {
  stages_.clear();
  used_ = 0;
  glQueryCounter(query(used_++), GL_TIMESTAMP);
}

void GlStageTimer::mark(const std::string& stage) {
  if (used_ == 0) return;  // begin() was not called
  glQueryCounter(query(used_++), GL_TIMESTAMP);
  stages_.push_back(stage);
}

std::vector<std::pair<std::string, double>> GlStageTimer::collect() {
  std::vector<std::pair<std::string, double>> out;
  if (used_ < 2) return out;
  std::vector<GLuint64> stamps(used_);
  for (std::size_t i = 0; i < used_; ++i) glGetQueryObjectui64v(pool_[i], GL_QUERY_RESULT, &stamps[i]);
  checkGl("reading GPU timers");
  for (std::size_t i = 0; i < stages_.size(); ++i) {
    const double ms = static_cast<double>(stamps[i + 1] - stamps[i]) * 1e-6;
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& p) { return p.first == stages_[i]; });
    if (it == out.end()) out.emplace_back(stages_[i], ms); else it->second += ms;
  }
  return out;
}

}  // namespace hf::gl
