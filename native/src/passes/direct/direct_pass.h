// Deferred direct diffuse lighting, one additive fullscreen draw per light: albedo / pi * E * V, with E the
// exact unshadowed irradiance (area lights: Lambert's polygon formula, clipped to the receiver's horizon) and V
// the shadow-map visibility (ShadowPass). Shaders: shaders/common/fullscreen.vert, shaders/direct/direct.frag,
// shaders/common/lights.glsl.
#pragma once

#include <functional>

#include "gl/objects.h"
#include "passes/gbuffer/gbuffer_pass.h"
#include "passes/render_context.h"
#include "passes/shadows/shadow_pass.h"

namespace bounce {

LightBlock make_light_block(const BounceLight& light);

class DirectPass {
 public:
  DirectPass();
  void execute(const RenderContext& context, const GBuffer& gbuffer, ShadowPass& shadows);
  // Each light's shadow map and LightBlock bound in turn for `use`, without drawing the direct light: Forward
  // Light Cuts lights its VPLs by them once per sample, before the tiles.
  void for_each_shadowed_light(const RenderContext& context, ShadowPass& shadows, const std::function<void()>& use);
  GLuint output() const { return direct_.id(); }  // RGBA32F

 private:
  gl::Program program_;
  gl::Texture direct_;
  gl::Framebuffer framebuffer_;
  gl::Buffer light_buffer_;
  int width_ = 0, height_ = 0;
};

}  // namespace bounce
