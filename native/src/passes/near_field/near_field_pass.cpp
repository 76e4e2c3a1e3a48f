#include "passes/near_field/near_field_pass.h"

#include "gl/shader.h"
#include "sampling.h"

namespace bounce {

NearFieldPass::NearFieldPass()
    : program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "near_field/near_field.frag"}})),
      second_program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "near_field/near_field_second.frag"}})) {}

void NearFieldPass::fit(const RenderContext& context) {
  if (width_ == context.width && height_ == context.height) return;
  light_ = gl::make_texture_2d(GL_RGBA32F, context.width, context.height);
  target_ = gl::make_framebuffer({light_.id()}, 0);
  width_ = context.width;
  height_ = context.height;
}

GLuint NearFieldPass::from_gbuffer(const RenderContext& context, const GBuffer& gbuffer, GLuint direct, float clamp,
                                   int blur_radius) {
  StageScope scope(context.timer, Stage::NearField);
  fit(context);
  glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
  glViewport(0, 0, context.width, context.height);
  gbuffer.bind_for_reading();
  glBindTextureUnit(8, direct);
  glUseProgram(program_.id());
  glUniformMatrix4fv(0, 1, GL_FALSE, &context.view_projection[0][0]);
  glUniformMatrix4fv(1, 1, GL_FALSE, &context.world_to_view[0][0]);
  glUniform1f(2, clamp);
  glUniform2i(3, context.tile_origin.x, context.tile_origin.y);
  glUniform1ui(4, hash_combine(context.seed, 0x4e464c00u + context.sample));
  draw_fullscreen_triangle();
  return blur_.run(light_.id(), gbuffer, blur_radius);
}

GLuint NearFieldPass::smoothed(const RenderContext& context, const GBuffer& gbuffer, GLuint traced, int blur_radius) {
  StageScope scope(context.timer, Stage::NearField);
  return blur_.run(traced, gbuffer, blur_radius);
}

GLuint NearFieldPass::second_bounce(const RenderContext& context, GLuint reflectance, GLuint source, GLuint unseen,
                                    GLuint indirect, GLuint second, GLuint near_field) {
  StageScope scope(context.timer, Stage::NearField);
  fit(context);
  glBindFramebuffer(GL_FRAMEBUFFER, target_.id());
  glViewport(0, 0, context.width, context.height);
  glBindTextureUnit(8, reflectance);
  glBindTextureUnit(9, source);
  glBindTextureUnit(10, indirect);
  glBindTextureUnit(11, second);
  glBindTextureUnit(12, near_field);
  glBindTextureUnit(13, unseen);
  glUseProgram(second_program_.id());
  draw_fullscreen_triangle();
  return light_.id();
}

}  // namespace bounce
