// The topology of the scene's empty space (native/topology), built once per geometry and topology settings and
// kept in a process-wide cache: the viewport, F12 renders and every frame of a batch render share it, and camera
// and light moves reuse it. The Topology method renders with it; Forward Light Cuts borrows it for indirect
// shadows.
#pragma once

#include <cstdint>
#include <memory>

#include "bounce/bounce.h"
#include "cpu/cpu_scene.h"
#include "render_callbacks.h"
#include "topology/topology.h"

namespace bounce::cpu {

class TopologyCache {
 public:
  // Every topology comes with the occluders inside clusters (topology/occluders.h), estimated from rays;
  // with_passages: the light through openings narrower than a voxel (topology/passages.h) too, for a renderer
  // without a ray per light (FLC; between clusters the gates do not join the Topology method casts shadow rays).
  // The methods share one entry per scene: the passages are added to a cached topology that lacks them, and a
  // cache without the need takes either.
  explicit TopologyCache(bool with_passages) : with_passages_(with_passages) {}
  // The topology of `scene` (synced) for settings.topology_resolution and topology_alpha: the process-wide
  // cache's, else this object's own when still valid, else built (or its ray estimates added), with its stages
  // reported through callbacks.status over the first half of the progress bar. nullptr when cancelled.
  std::shared_ptr<const topology::Topology> get(const CpuScene& scene, const BounceSettings& settings,
                                                const RenderCallbacks& callbacks);
  const std::shared_ptr<const topology::Topology>& latest() const { return topology_; }  // the last get()'s

 private:
  std::shared_ptr<const topology::Topology> topology_;
  uint64_t key_ = 0;
  bool with_passages_;
};

// How many topologies the process-wide cache has built (bounce_topology_info).
uint64_t topology_builds();

}  // namespace bounce::cpu
