#include "stage_timer.h"

#include <cstring>

namespace bounce {

const char* stage_name(Stage stage) {
  switch (stage) {
    case Stage::GBuffer:
      return "G-buffer";
    case Stage::Shadows:
      return "Shadows";
    case Stage::Direct:
      return "Direct";
    case Stage::Compose:
      return "Compose";
    case Stage::Readback:
      return "Readback";
    default:
      return "?";
  }
}

void StageTimer::begin(Stage stage) {
  gl::Query query;
  if (!free_.empty()) {
    query = std::move(free_.back());
    free_.pop_back();
  } else {
    GLuint id = 0;
    glGenQueries(1, &id);
    query = gl::Query(id);
  }
  glBeginQuery(GL_TIME_ELAPSED, query.id());
  pending_.push_back({stage, std::move(query)});
  current_ = stage;
  started_ = std::chrono::steady_clock::now();
}

void StageTimer::end() {
  glEndQuery(GL_TIME_ELAPSED);
  const std::chrono::duration<double, std::milli> elapsed = std::chrono::steady_clock::now() - started_;
  cpu_ms_[static_cast<int>(current_)] += elapsed.count();
  current_ = Stage::Count;
}

void StageTimer::resolve() {
  for (Pending& p : pending_) {
    GLuint64 nanoseconds = 0;
    glGetQueryObjectui64v(p.query.id(), GL_QUERY_RESULT, &nanoseconds);
    gpu_ms_[static_cast<int>(p.stage)] += static_cast<double>(nanoseconds) * 1e-6;
    free_.push_back(std::move(p.query));
  }
  pending_.clear();
}

void StageTimer::reset() {
  resolve();
  gpu_ms_.fill(0.0);
  cpu_ms_.fill(0.0);
}

void StageTimer::fill(BounceFrameInfo& info) const {
  info.stage_count = static_cast<int32_t>(Stage::Count);
  for (int i = 0; i < info.stage_count; ++i) {
    std::strncpy(info.stages[i].name, stage_name(static_cast<Stage>(i)), sizeof info.stages[i].name - 1);
    info.stages[i].gpu_ms = gpu_ms_[i];
    info.stages[i].cpu_ms = cpu_ms_[i];
  }
}

}  // namespace bounce
