// How much of the light a direction of the world sends reaches what the camera sees, per bin of direction
// (sampling.h, sphere_bins), learned over a render's samples: the guide by which the sample's world directions are
// drawn for the GPU methods (SceneLights::guide_world). Drawn from the environment's table alone, a sky's
// directions mostly light what the camera does not see: the roofs around Sponza's court, the outside of a room's
// walls. Which of a sample's few directions reached the court decided its whole first bounce (0.34 to 3.34 of
// Cycles' over eight seeds under forest.exr). From each of the view probes a path of one bounce asks, for one
// direction in every bin, whether the surfaces it meets see the sky there: the reach of a bin is the radiance a
// sun of unit irradiance from it would give the probes' surfaces (their first bounce, and their direct light when
// the sample's suns light the direct pass too), averaged over the probes and the samples so far.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "cpu/cpu_scene.h"
#include "cpu/view_probes.h"

namespace bounce::cpu {

class WorldReach {
 public:
  static constexpr int kPathsPerProbe = 4;  // cosine-distributed rays from each probe's surface

  // Forgets what was learned: the view or the scene changed.
  void reset();
  // Learns one sample more from `probes` (each a surface the camera sees); `direct`: the suns light the direct pass
  // too. Deterministic for a key.
  void learn(const CpuScene& scene, std::span<const ViewProbe> probes, bool direct, uint32_t key);
  // Per bin, the mean reach so far; empty until something has been learned that reaches the view.
  std::span<const float> reach() const;

 private:
  std::vector<double> sum_;  // per bin
  std::vector<float> mean_;
  uint64_t probes_learned_ = 0;
};

}  // namespace bounce::cpu
