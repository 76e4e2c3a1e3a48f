#include "stage_timer.h"

#include <algorithm>
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
    case Stage::TracedDirect:
      return "Direct (ray traced)";
    case Stage::WorldGuide:
      return "World guide";
    case Stage::FlcRegular:
      return "FLC regular";
    case Stage::FlcDivergent:
      return "FLC divergent";
    case Stage::FlcLighting:
      return "FLC VPL lighting";
    case Stage::FlcSplat:
      return "FLC splat";
    case Stage::FlcResolve:
      return "FLC untile + blur";
    case Stage::FlcRayChecks:
      return "FLC ray checks";
    case Stage::TopologyVisibility:
      return "Topology visibility";
    case Stage::SsvpRsm:
      return "SSVP RSM";
    case Stage::SsvpCluster:
      return "SSVP sampling + clustering";
    case Stage::SsvpImportance:
      return "SSVP VPL importance";
    case Stage::SsvpParaboloids:
      return "SSVP paraboloids";
    case Stage::SsvpShade:
      return "SSVP shading";
    case Stage::SsvpRayChecks:
      return "SSVP ray checks";
    case Stage::SsvpDenoise:
      return "SSVP denoise";
    case Stage::NearField:
      return "Near field";
    case Stage::TopologyPrecompute:
      return "Topology Precompute";
    case Stage::TopologyVpls:
      return "Topology VPLs";
    case Stage::TopologyPrimary:
      return "Topology Primary";
    case Stage::TopologyDirect:
      return "Topology Direct";
    case Stage::TopologyAssign:
      return "Topology Assign";
    case Stage::TopologyIndirect:
      return "Topology Indirect";
    case Stage::TopologyDebug:
      return "Topology Debug";
    case Stage::Compose:
      return "Compose";
    case Stage::Readback:
      return "Readback";
    default:
      return "?";
  }
}

void StageTimer::begin(Stage stage) {
  used_[static_cast<int>(stage)] = true;
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
  used_.fill(false);
}

void StageTimer::fill(BounceFrameInfo& info) const {
  info.stage_count = 0;
  for (int i = 0; i < static_cast<int>(Stage::Count); ++i) {
    if (!used_[i]) continue;
    BounceStageTime& out = info.stages[info.stage_count++];
    std::strncpy(out.name, stage_name(static_cast<Stage>(i)), sizeof out.name - 1);
    out.gpu_ms = gpu_ms_[i];
    out.cpu_ms = cpu_ms_[i];
  }
}

double StageTimer::milliseconds(Stage stage) const {
  const auto i = static_cast<std::size_t>(stage);
  return std::max(gpu_ms_[i], cpu_ms_[i]);
}

double StageTimer::total_milliseconds() const {
  double total = 0.0;
  for (int i = 0; i < static_cast<int>(Stage::Count); ++i) total += milliseconds(static_cast<Stage>(i));
  return total;
}

}  // namespace bounce
