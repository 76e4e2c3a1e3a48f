// Per-stage GPU times from GL timer queries (GL_TIME_ELAPSED) plus render-thread wall time.
#pragma once

#include <array>
#include <chrono>
#include <vector>

#include "bounce/bounce.h"
#include "gl/objects.h"

namespace bounce {

enum class Stage {
  GBuffer,
  Shadows,
  Direct,
  TracedDirect,        // direct light by Embree shadow rays (CPU), G-buffer readback and upload included
  WorldGuide,          // where the world's directions reach the view (CPU, Embree: cpu/world_reach.h)
  FlcRegular,          // Forward Light Cuts: regular pipeline (decimation, partition, VPLs)
  FlcDivergent,        // subdivision of the divergent triangles
  FlcLighting,         // direct irradiance at the VPLs
  FlcSplat,            // splatting into the interleaved sub-images
  FlcResolve,          // untiling and blur
  FlcRayChecks,        // Ray Checks: the checked pairs read back, their shadow rays (CPU, Embree), the correction
  TopologyVisibility,  // the pixels' visibility clusters (Forward Light Cuts' Indirect Shadows)
  SsvpRsm,             // Screen-Space VPL Propagation: the bouncing lights' reflective shadow maps
  SsvpCluster,         // first-bounce sampling, k-means, second-bounce propagation (the paper's "Misc")
  SsvpImportance,      // VPL Importance: probes read back, shadow rays to them, resampling (CPU, Embree)
  SsvpParaboloids,     // one paraboloid map per cluster
  SsvpShade,           // interleaved shading of both bounces, debug view
  SsvpRayChecks,       // Ray Checks: the checked pairs read back, their shadow rays (CPU, Embree), the correction
  SsvpDenoise,         // geometry-aware blur
  NearField,           // the light the VPLs' distance clamp takes, from the G-buffer (FLC, SSVP)
  TopologyPrecompute,  // the topology of the empty space (cached: only the first render of a scene)
  TopologyVpls,        // VPL paths from the lights (CPU, Embree)
  TopologyPrimary,     // primary rays and the view samples' visibility clusters
  TopologyDirect,      // direct light by shadow rays
  TopologyAssign,      // geometry clusters and light assignment (paper Sec. V.B-C)
  TopologyIndirect,    // gathering the assigned VPLs (Sec. V.D)
  TopologyDebug,       // the Topology pass
  Compose,
  Readback,
  Count
};

const char* stage_name(Stage stage);

class StageTimer {
 public:
  void begin(Stage stage);
  void end();
  void resolve();  // waits for the queries issued since the last resolve and adds them up
  void reset();
  void fill(BounceFrameInfo& info) const;
  // A stage's time since the last reset: its GPU time, or its render-thread time where that is longer (CPU stages).
  double milliseconds(Stage stage) const;
  double total_milliseconds() const;  // of every stage

 private:
  struct Pending {
    Stage stage;
    gl::Query query;
  };
  std::vector<Pending> pending_;
  std::vector<gl::Query> free_;
  std::array<double, static_cast<int>(Stage::Count)> gpu_ms_{}, cpu_ms_{};
  std::array<bool, static_cast<int>(Stage::Count)> used_{};  // only stages that ran are reported
  Stage current_ = Stage::Count;
  std::chrono::steady_clock::time_point started_;
};

// Scoped begin/end.
class StageScope {
 public:
  StageScope(StageTimer& timer, Stage stage) : timer_(timer) { timer_.begin(stage); }
  ~StageScope() { timer_.end(); }
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  StageTimer& timer_;
};

}  // namespace bounce
