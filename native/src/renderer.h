// Renders a frame on the render thread: the average of settings.samples progressive samples, each over tiles of one
// size, at most settings.tile_size pixels. A sample first does what does not depend on the view, once for all its
// tiles: [FLC VPLs -> their lighting by each light's shadow map]; then each tile runs G-buffer -> direct light (shadow
// maps, rendered by the first tile that needs them and reused by the others; or Embree rays) -> [pixels'
// visibility clusters] -> [FLC splat | SSVP] -> [near field] -> compose. The Topology method renders on the CPU instead
// (cpu::TopologyRenderer).
#pragma once

#include <functional>
#include <memory>

#include <glm/glm.hpp>

#include "bounce/bounce.h"
#include "cost_model.h"
#include "cpu/scene_analysis.h"
#include "cpu/topology_renderer.h"
#include "cpu/world_reach.h"
#include "frame.h"
#include "frame_plan.h"
#include "gpu_scene.h"
#include "passes/compose/compose_pass.h"
#include "passes/direct/direct_pass.h"
#include "passes/direct/traced_direct_pass.h"
#include "passes/flc/flc_pass.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/near_field/near_field_pass.h"
#include "passes/shadows/shadow_pass.h"
#include "passes/ssvp/ssvp_pass.h"
#include "passes/topology_visibility/topology_visibility_pass.h"
#include "render_callbacks.h"
#include "scene_lights.h"
#include "stage_timer.h"

namespace bounce {

// The crop-and-jitter matrix that maps the clip space of the whole image to that of a tile, with the sample
// offset `jitter` in pixels. Exposed for tests.
glm::mat4 tile_matrix(int image_width, int image_height, int x0, int y0, int width, int height, glm::vec2 jitter);

class Renderer {
 public:
  Renderer();
  GpuScene& scene() { return scene_; }
  // The topology the last TOPOLOGY render used; nullptr before one.
  std::shared_ptr<const topology::Topology> topology() const { return topology_.topology(); }
  // Returns false when cancelled. Method AUTO renders with plan_auto's choice for the scene seen from `camera`.
  bool render(const BounceSettings& settings, const BounceCamera& camera, const RenderCallbacks& callbacks);

 private:
  // The explicit methods.
  bool render_method(const BounceSettings& settings, const BounceCamera& camera, const RenderCallbacks& callbacks);
  // The scene's analysis from `camera`, redone when the scene changed or the camera moved or turned noticeably
  // (navigating the viewport keeps the plan, so the image does not switch methods at every step).
  const cpu::SceneAnalysis& analysis(const BounceSettings& settings, const BounceCamera& camera);
  // Uploads and binds shaders/common/emitter_occluders.glsl's buffer: a count, then the occluders.
  void bind_emitter_occluders(const std::vector<EmitterOccluder>& occluders);

  GpuScene scene_;
  SceneLights scene_lights_;
  cpu::CpuScene cpu_scene_;      // Embree's copy of the scene: ray-traced direct light and the Topology method
  cpu::WorldReach world_reach_;  // learned over a render's samples, for FramePlan::guide_world
  StageTimer timer_;
  CostModel& costs_;            // Auto's: this device's (the GL renderer's and the CPU threads')
  gl::Buffer settings_buffer_;  // the `Settings` uniform block of every shader
  gl::Buffer emitter_occluders_;
  std::size_t emitter_occluders_bytes_ = 0;
  GBufferPass gbuffer_;
  ShadowPass shadows_;
  DirectPass direct_;
  TracedDirectPass traced_direct_;
  FlcPass flc_;
  cpu::TopologyCache flc_topologies_{true};  // Forward Light Cuts' Indirect Shadows
  TopologyVisibilityPass topology_visibility_;
  SsvpPass ssvp_;
  NearFieldPass near_field_;
  ComposePass compose_;
  cpu::TopologyRenderer topology_{cpu_scene_};
  struct AnalysisKey {
    uint64_t geometry = 0, lights = 0, world = 0;
    glm::vec3 eye{0.0f}, forward{0.0f};
  } analysis_key_;
  cpu::SceneAnalysis analysis_;
};

}  // namespace bounce
