// The first bounce's light next to lit surfaces, which the VPL methods' distance clamp takes (Kollig and Keller
// 2006's bias compensation, cpu/near_field.h), blurred like the indirect light: traced by Embree rays with the
// direct light (TracedDirectPass), or here, where the direct light comes from shadow maps, by short cosine rays
// marched through the G-buffer, which give back L_direct (1 - d^2 / c^2) of the visible surfaces within the clamp
// c. With the traced rays, second_bounce gives back the second bounce's share too. Shaders:
// shaders/common/fullscreen.vert, shaders/near_field/near_field.frag, shaders/near_field/near_field_second.frag.
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
  // The second bounce's light next to lit surfaces (irradiance / pi; valid until the next call): each pixel's ray
  // met a surface y of `reflectance` that receives the first-bounce irradiance of pixel `source`
  // (TracedDirectPass::near_field_reflectance and near_field_source), there `indirect` (both bounces) less `second`
  // plus `near_field` (this pass's first bounce), all irradiance / pi; where no pixel's is, `unseen`
  // (TracedDirectPass::near_field_unseen). Not blurred: its inputs are, and a blur of
  // its own cost 200-250 ms of a 1280x720 sample on llvmpipe for no gain measured (Sponza's second-bounce relMSE
  // 4x4 1.31e-5 without, 1.33e-5 with).
  GLuint second_bounce(const RenderContext& context, GLuint reflectance, GLuint source, GLuint unseen, GLuint indirect,
                       GLuint second, GLuint near_field);

 private:
  // Allocates light_ and target_ at the context's size.
  void fit(const RenderContext& context);

  gl::Program program_, second_program_;
  gl::Texture light_;
  gl::Framebuffer target_;
  GeometryBlur blur_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
