// Direct diffuse light with Embree shadow rays instead of shadow maps (Shadows > Method: Ray Traced). The
// G-buffer's positions, normals and albedo are read back together (one wait for the GPU), each pixel is lit on
// the CPU by cpu/direct_light (the light model of shaders/common/lights.glsl, with the visible fraction of each
// light from one jittered shadow ray per light and sample, through alpha cut-outs), and albedo / pi * E is
// uploaded as the sample's direct light. Shadow maps blur and shift shadow edges by a texel (sunlit stripes
// through blinds came out a pixel too wide) and leak through thin closed walls; rays do neither. With a near-field
// clamp it also traces, per pixel, the ray of cpu/near_field.h: the first bounce's light that a VPL method's
// distance clamp takes. No shaders: the pass runs on the CPU threads.
#pragma once

#include <vector>

#include <glm/vec4.hpp>

#include "cpu/cpu_scene.h"
#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"
#include "scene_lights.h"

namespace bounce {

class TracedDirectPass {
 public:
  // `lights`: the sample's list came from it (its world's directions are one of two strategies, direct_light.h).
  // `near_field_clamp`: the VPL method's distance clamp in metres, 0 for none.
  void execute(const RenderContext& context, const GBuffer& gbuffer, const cpu::CpuScene& scene,
               const SceneLights& lights, float near_field_clamp);
  GLuint output() const { return direct_.id(); }          // RGBA32F, as DirectPass::output()
  GLuint near_field() const { return near_field_.id(); }  // RGBA32F, irradiance / pi; stale without a clamp

 private:
  gl::Texture direct_, near_field_;
  int width_ = 0, height_ = 0;
  gl::TextureReadback gbuffer_readback_;
  std::vector<glm::vec4> light_, near_light_;
};

}  // namespace bounce
