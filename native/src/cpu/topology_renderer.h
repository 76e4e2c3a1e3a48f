// The topology method's renderer (Noel and Biri 2014, Sec. V), on the CPU with Embree: primary rays give each
// view sample its surface and visibility cluster; direct light comes from Bounce's direct-lighting model with
// shadow rays; VPLs traced from the lights bring the indirect light, each lighting the view samples of its own
// visibility cluster without a test and those of other clusters only inside the cones through its cluster's
// gates (Fig. 11), assigned per geometry cluster of clustered shading (Sec. V.B-C). The topology comes from
// TopologyCache: built on the first render of a scene, then shared.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "bounce/bounce.h"
#include "cpu/cpu_scene.h"
#include "cpu/sky_guide.h"
#include "cpu/topology_cache.h"
#include "cpu/vpls.h"
#include "gpu_scene.h"
#include "render_callbacks.h"
#include "scene_lights.h"
#include "stage_timer.h"
#include "topology/topology.h"

namespace bounce::cpu {

struct ClusterGraph;

class TopologyRenderer {
 public:
  explicit TopologyRenderer(CpuScene& scene) : scene_(scene) {}
  // Renders settings.samples progressive samples of the whole crop (no tiles: nothing is on the GPU). Returns
  // false when cancelled, the precomputation included.
  // Each sample is lit by `lights`' list for it.
  bool render(const GpuScene& scene, SceneLights& lights, const BounceSettings& settings, const BounceCamera& camera,
              const RenderCallbacks& callbacks, StageTimer& timer);
  std::shared_ptr<const topology::Topology> topology() const { return topologies_.latest(); }

 private:
  // A view sample the VPLs' importance is measured at.
  struct Probe {
    glm::vec3 position, normal, albedo;
    uint32_t cluster;
    std::span<const topology::Occluders::Hit> occluder_hits;  // of its cell (topology::cell_hits)
  };
  void prepare_vpls(std::span<const BounceLight> lights, const SceneLights& scene_lights,
                    const BounceSettings& settings, uint64_t seed, std::span<const Probe> probes,
                    const ClusterGraph& graph);
  uint32_t vpl_cluster(const Vpl& vpl) const;

  CpuScene& scene_;                  // the renderer's, shared with the ray-traced direct light
  TopologyCache topologies_{false};  // occluders, no passages: shadow rays decide there
  std::vector<Vpl> vpls_;
  std::vector<EmissionGuide> guides_;    // per lamp, learned over a render's samples
  PathShares path_shares_;               // learned over a render's samples
  LandingGuide world_guide_;             // learned over a render's samples
  SkyGuide sky_guide_;                   // learned over a render's samples
  std::vector<uint32_t> vpl_cluster_;    // per VPL; topology::kNoNode when walled in or outside the grid
  std::vector<uint8_t> vpl_lit_by_ray_;  // per VPL: whether a shadow ray found its light reaching a probe
};

}  // namespace bounce::cpu
