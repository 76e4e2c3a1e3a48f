// The first bounce's light next to lit surfaces, which the VPL methods' distance clamp takes (Kollig and Keller
// 2006's bias compensation, cpu/near_field.h), blurred like the indirect light: traced by Embree rays with the
// direct light (TracedDirectPass), or here, where the direct light comes from shadow maps, by short cosine rays
// marched through the G-buffer, which give back L_direct (1 - d^2 / c^2) of the visible surfaces within the clamp
// c. Shaders: shaders/common/fullscreen.vert, shaders/near_field/near_field.frag.
#pragma once

#include "gl/objects.h"
#include "passes/blur/geometry_blur.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"

namespace bounce {

class NearFieldPass {
 public:
  NearFieldPass();
  // `direct`: the sample's Direct target (reflected radiance). `clamp`: c, metres. Both return irradiance / pi
  // (RGBA32F, the G-buffer's size), valid until the next call.
  GLuint from_gbuffer(const RenderContext& context, const GBuffer& gbuffer, GLuint direct, float clamp,
                      int blur_radius);
  GLuint smoothed(const RenderContext& context, const GBuffer& gbuffer, GLuint traced, int blur_radius);

 private:
  gl::Program program_;
  gl::Texture light_;
  gl::Framebuffer target_;
  GeometryBlur blur_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
