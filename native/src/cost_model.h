// Auto's cost model: what a progressive sample costs on this machine, learned from the samples this engine has
// rendered (no constant tuned elsewhere). Per method and bounce count, the time per pixel of a sample is a line in
// the method's VPL count (vpl_setting), fitted by least squares to the last frames; while they all had one VPL
// count, the stage timer's share of the VPL stages (tracing or importance sampling, and shading) gives the slope.
// Engines share the process's model (shared()): a final render is a new engine, and the machine is the same.
#pragma once

#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "bounce/bounce.h"

namespace bounce {

// The setting a method's sample cost grows with: Topology's VPLs (paths times bounces), SSVP's first-bounce VPLs
// (the second bounce's follow them); none for the other methods. `name` is its row in settings.def.
struct VplSetting {
  int32_t BounceSettings::*member;
  const char* name;
};
inline std::optional<VplSetting> vpl_setting(int32_t method) {
  if (method == BOUNCE_METHOD_TOPOLOGY) return VplSetting{&BounceSettings::topology_vpls, "topology_vpls"};
  if (method == BOUNCE_METHOD_SSVP) return VplSetting{&BounceSettings::ssvp_vpls, "ssvp_vpls"};
  return std::nullopt;
}

struct SampleCost {
  double fixed_ms = 0.0;    // what does not depend on the VPL count: G-buffer, shadows, direct light, clustering
  double per_vpl_ms = 0.0;  // per VPL of vpl_setting
  double at(int vpls) const { return fixed_ms + per_vpl_ms * vpls; }
};

class CostModel {
 public:
  static CostModel& shared();

  // A rendered frame of `settings` at `pixels` pixels whose samples took `sample_ms` each on average, of which
  // the share `vpl_share` was spent on work proportional to its VPL count (vpl_setting).
  void observe(const BounceSettings& settings, int64_t pixels, double sample_ms, double vpl_share);
  // The cost of a sample of `method` with `bounces` at `pixels` pixels; none before a frame of it was observed.
  std::optional<SampleCost> predict(int32_t method, int32_t bounces, int64_t pixels) const;

 private:
  struct Observation {
    double vpls, ms_per_pixel, vpl_share;
  };
  static constexpr std::size_t kKept = 8;  // frames per plan: the model follows a scene that changed
  mutable std::mutex mutex_;
  std::map<std::pair<int32_t, int32_t>, std::deque<Observation>> costs_;
};

}  // namespace bounce
