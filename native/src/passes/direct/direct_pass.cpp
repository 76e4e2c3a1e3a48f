#include "passes/direct/direct_pass.h"

#include <cstring>

#include "gl/shader.h"

namespace bounce {

LightBlock make_light_block(const BounceLight& light) {
  LightBlock block{};
  std::memcpy(block.position_type, light.position, sizeof light.position);
  block.position_type[3] = static_cast<float>(light.type);
  std::memcpy(block.axis_x, light.axis_x, sizeof light.axis_x);
  std::memcpy(block.axis_y, light.axis_y, sizeof light.axis_y);
  std::memcpy(block.axis_z, light.axis_z, sizeof light.axis_z);
  std::memcpy(block.intensity, light.intensity, sizeof light.intensity);
  block.shape[0] = light.radius;
  block.shape[1] = light.half_size[0];
  block.shape[2] = light.half_size[1];
  block.shape[3] = light.spot_half_angle;
  block.spot_sun[0] = light.spot_blend;
  block.spot_sun[1] = light.spot_cos_falloff ? 1.0f : 0.0f;
  block.spot_sun[2] = light.sun_angle;
  std::memcpy(block.triangle, light.triangle, sizeof light.triangle);
  block.shadow_view_projection = glm::mat4(1.0f);
  return block;
}

DirectPass::DirectPass()
    : program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "direct/direct.frag"}})),
      light_buffer_(gl::make_buffer(sizeof(LightBlock), nullptr)) {}

void DirectPass::execute(const RenderContext& context, const GBuffer& gbuffer, ShadowPass& shadows) {
  if (width_ != context.width || height_ != context.height) {
    direct_ = gl::make_texture_2d(GL_RGBA32F, context.width, context.height);
    framebuffer_ = gl::make_framebuffer({direct_.id()}, 0);
    width_ = context.width;
    height_ = context.height;
  }
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearNamedFramebufferfv(framebuffer_.id(), GL_COLOR, 0, zero);
  for_each_shadowed_light(context, shadows, [&] {
    StageScope scope(context.timer, Stage::Direct);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glViewport(0, 0, context.width, context.height);
    gbuffer.bind_for_reading();
    glUseProgram(program_.id());
    glUniform2i(0, context.tile_origin.x, context.tile_origin.y);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    draw_fullscreen_triangle();
    glDisable(GL_BLEND);
  });
}

void DirectPass::for_each_shadowed_light(const RenderContext& context, ShadowPass& shadows,
                                         const std::function<void()>& use) {
  const auto& lights = context.lights;
  shadows.trim(lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    LightBlock block = make_light_block(lights[i]);
    shadows.prepare(context, i, lights[i], block);
    glNamedBufferSubData(light_buffer_.id(), 0, sizeof block, &block);
    glBindBufferBase(GL_UNIFORM_BUFFER, binding::kLightBlock, light_buffer_.id());
    use();
  }
}

}  // namespace bounce
