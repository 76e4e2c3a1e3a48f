// The topology method's renderer (Noel and Biri 2014, Sec. V), on the CPU with Embree: primary rays give each
// view sample its surface and visibility cluster; direct light comes from Bounce's direct-lighting model with
// shadow rays; VPLs traced from the lights bring the indirect light, each lighting the view samples of its own
// visibility cluster without a test and those of other clusters only inside the cones through its cluster's
// gates (Fig. 11), assigned per geometry cluster of clustered shading (Sec. V.B-C). The topology is built on
// the first render of a scene and cached by a hash of the geometry and the topology settings, in the process,
// so the viewport, F12 renders and every frame of a batch render share it; camera and light moves reuse it.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bounce/bounce.h"
#include "cpu/cpu_scene.h"
#include "cpu/vpls.h"
#include "gpu_scene.h"
#include "render_callbacks.h"
#include "stage_timer.h"
#include "topology/topology.h"

namespace bounce::cpu {

class TopologyRenderer {
 public:
  // Renders settings.samples progressive samples of the whole crop (no tiles: nothing is on the GPU). Returns
  // false when cancelled, the precomputation included.
  bool render(const GpuScene& scene, const BounceSettings& settings, const BounceCamera& camera,
              const RenderCallbacks& callbacks, StageTimer& timer);
  std::shared_ptr<const topology::Topology> topology() const { return topology_; }

 private:
  bool prepare_topology(const BounceSettings& settings, const RenderCallbacks& callbacks);
  void prepare_vpls(const GpuScene& scene, const BounceSettings& settings, uint32_t seed);

  CpuScene scene_;
  std::shared_ptr<const topology::Topology> topology_;
  uint64_t topology_key_ = 0;
  std::vector<Vpl> vpls_;
  std::vector<uint32_t> vpl_cluster_;  // per VPL; topology::kNoNode when walled in or outside the grid
  uint64_t vpl_key_ = 0;
};

// How many topologies the process-wide cache behind TopologyRenderer has built (bounce_topology_info).
uint64_t topology_builds();

}  // namespace bounce::cpu
