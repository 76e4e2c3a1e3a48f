// Direct diffuse light with Embree shadow rays instead of shadow maps (Shadows > Method: Ray Traced). The
// G-buffer's positions, normals and albedo are read back together (one wait for the GPU), each pixel is lit on
// the CPU by cpu/direct_light (the light model of shaders/common/lights.glsl, with the visible fraction of each
// light from one jittered shadow ray per light and sample, through alpha cut-outs), and albedo / pi * E is
// uploaded as the sample's direct light. Shadow maps blur and shift shadow edges by a texel (sunlit stripes
// through blinds came out a pixel too wide) and leak through thin closed walls; rays do neither. With a near-field
// clamp it also traces, per pixel, the ray of cpu/near_field.h: the first bounce's light that a VPL method's
// distance clamp takes, and for a method with a second bounce, what the surface the ray met reflects and where the
// camera sees that surface, for NearFieldPass::second_bounce, or, where it does not, that surface's first bounce
// from the method's VPLs. No shaders: the pass runs on the CPU threads.
#pragma once

#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "cpu/cpu_scene.h"
#include "cpu/vpls.h"
#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"
#include "scene_lights.h"

namespace bounce {

class TracedDirectPass {
 public:
  // What the near field's rays give back of a VPL method's distance clamp.
  struct NearFieldRays {
    float clamp = 0.0f;          // metres; 0: no rays
    bool second_bounce = false;  // the second bounce's share too (near_field_reflectance, near_field_source)
    // The sample's first-bounce VPLs, for the second bounce's share where no pixel sees the surface a ray met
    // (near_field_unseen); none: nothing there.
    std::span<const cpu::Vpl> first_bounce_vpls;
  };
  // `lights`: the sample's list came from it (its world's directions are one of two strategies, direct_light.h).
  void execute(const RenderContext& context, const GBuffer& gbuffer, const cpu::CpuScene& scene,
               const SceneLights& lights, NearFieldRays near_field);
  GLuint output() const { return direct_.id(); }          // RGBA32F, as DirectPass::output()
  GLuint near_field() const { return near_field_.id(); }  // RGBA32F, irradiance / pi; stale without a clamp
  // For the second bounce's share; stale without it. RGBA32F: the reflectance of the surface y a pixel's ray met
  // (NearField::reflectance). R32I: the index (row * width + column) of the pixel whose first-bounce irradiance y
  // receives (cpu::first_bounce_pixel), -1 for none.
  GLuint near_field_reflectance() const { return near_field_reflectance_.id(); }
  GLuint near_field_source() const { return near_field_source_.id(); }
  // RGBA32F: irradiance / pi of the second bounce's share where the source is -1: the reflectance times the first
  // bounce that the VPLs give the surface no pixel sees (cpu::UnseenFirstBounce).
  GLuint near_field_unseen() const { return near_field_unseen_.id(); }

 private:
  gl::Texture direct_, near_field_, near_field_reflectance_, near_field_source_, near_field_unseen_;
  int width_ = 0, height_ = 0;
  gl::TextureReadback gbuffer_readback_;
  std::vector<glm::vec4> light_, near_light_, near_reflectance_, near_unseen_;
  std::vector<int32_t> near_source_;
};

}  // namespace bounce
