#include "passes/gbuffer/gbuffer_pass.h"

#include <glm/gtc/type_ptr.hpp>

#include "gl/shader.h"

namespace bounce {

void GBuffer::bind_for_reading() const {
  glBindTextureUnit(1, albedo.id());
  glBindTextureUnit(2, normal.id());
  glBindTextureUnit(3, position.id());
  glBindTextureUnit(4, emission.id());
  glBindTextureUnit(5, geometric_normal.id());
}

GBufferPass::GBufferPass()
    : program_(gl::build_program(
          {{GL_VERTEX_SHADER, "gbuffer/gbuffer.vert"}, {GL_FRAGMENT_SHADER, "gbuffer/gbuffer.frag"}})) {}

void GBufferPass::resize(int width, int height) {
  if (gbuffer_.width == width && gbuffer_.height == height) return;
  GBuffer g;
  g.albedo = gl::make_texture_2d(GL_RGBA16F, width, height);
  g.normal = gl::make_texture_2d(GL_RGBA16F, width, height);
  g.position = gl::make_texture_2d(GL_RGBA32F, width, height);
  g.emission = gl::make_texture_2d(GL_RGBA16F, width, height);
  g.geometric_normal = gl::make_texture_2d(GL_RGBA16F, width, height);
  g.depth = gl::make_texture_2d(GL_DEPTH_COMPONENT32F, width, height);
  g.framebuffer = gl::make_framebuffer(
      {g.albedo.id(), g.normal.id(), g.position.id(), g.emission.id(), g.geometric_normal.id()}, g.depth.id());
  g.width = width;
  g.height = height;
  gl::check("allocating the G-buffer");
  gbuffer_ = std::move(g);
}

void GBufferPass::execute(const RenderContext& context) {
  StageScope scope(context.timer, Stage::GBuffer);
  resize(context.width, context.height);
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer_.framebuffer.id());
  glViewport(0, 0, context.width, context.height);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int i = 0; i < 5; ++i) glClearBufferfv(GL_COLOR, i, zero);
  const float far_depth = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &far_depth);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glUseProgram(program_.id());
  glUniformMatrix4fv(binding::kViewProjection, 1, GL_FALSE, glm::value_ptr(context.view_projection));
  glUniform3fv(3, 1, glm::value_ptr(context.camera_position));
  glUniformMatrix4fv(4, 1, GL_FALSE, glm::value_ptr(context.world_to_view));
  glUniform1i(5, context.orthographic ? 1 : 0);
  glUniform3fv(6, 1, glm::value_ptr(context.camera_forward));
  context.scene.draw();
  glDisable(GL_DEPTH_TEST);
}

}  // namespace bounce
