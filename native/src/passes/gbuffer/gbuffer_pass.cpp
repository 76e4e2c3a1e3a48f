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

GBuffer make_gbuffer(int width, int height) {
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
  gl::check("allocating a G-buffer");
  return g;
}

void GBufferPass::execute(const RenderContext& context) {
  StageScope scope(context.timer, Stage::GBuffer);
  if (gbuffer_.width != context.width || gbuffer_.height != context.height)
    gbuffer_ = make_gbuffer(context.width, context.height);
  const GBufferView view{context.view_projection, context.world_to_view, context.camera_position,
                         context.camera_forward,  context.orthographic,  {0, 0, context.width, context.height}};
  render(gbuffer_, {&view, 1}, context.scene);
}

void GBufferPass::render(GBuffer& target, std::span<const GBufferView> views, const GpuScene& scene) const {
  glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer.id());
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  for (int i = 0; i < 5; ++i) glClearBufferfv(GL_COLOR, i, zero);
  const float far_depth = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &far_depth);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glUseProgram(program_.id());
  for (const GBufferView& view : views) {
    glViewport(view.viewport.x, view.viewport.y, view.viewport.z, view.viewport.w);
    glUniformMatrix4fv(binding::kViewProjection, 1, GL_FALSE, glm::value_ptr(view.view_projection));
    glUniform3fv(3, 1, glm::value_ptr(view.eye));
    glUniformMatrix4fv(4, 1, GL_FALSE, glm::value_ptr(view.world_to_view));
    glUniform1i(5, view.orthographic ? 1 : 0);
    glUniform3fv(6, 1, glm::value_ptr(view.forward));
    scene.draw();
  }
  glDisable(GL_DEPTH_TEST);
}

}  // namespace bounce
