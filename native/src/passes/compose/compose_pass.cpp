#include "passes/compose/compose_pass.h"

#include <algorithm>

#include "common/parallel.h"
#include "gl/shader.h"

namespace bounce {

ComposePass::ComposePass()
    : program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "compose/compose.frag"}})),
      add_times_albedo_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "compose/add_times_albedo.frag"}})),
      slots_(1) {}

void ComposePass::keep_slots(int count) { slots_.resize(std::size_t(std::max(count, 1))); }

void ComposePass::clear(int slot, int width, int height) {
  Targets& targets = slots_.at(std::size_t(slot));
  if (targets.width != width || targets.height != height) {
    std::vector<GLuint> ids;
    for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov) {
      targets.textures[aov] = gl::make_texture_2d(aov == BOUNCE_AOV_DEPTH ? GL_R32F : GL_RGBA32F, width, height);
      if (aov < kComposedAovs) ids.push_back(targets.textures[aov].id());
    }
    targets.framebuffer = gl::make_framebuffer(ids, 0);
    targets.second_bounce_framebuffer = gl::make_framebuffer({targets.textures[BOUNCE_AOV_SECOND_BOUNCE].id()}, 0);
    gl::check("allocating the accumulation targets");
    targets.width = width;
    targets.height = height;
  }
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float background_depth[4] = {1e10f, 0.0f, 0.0f, 0.0f};
  for (int aov = 0; aov < kComposedAovs; ++aov)
    glClearNamedFramebufferfv(targets.framebuffer.id(), GL_COLOR, aov,
                              aov == BOUNCE_AOV_DEPTH ? background_depth : zero);
  glClearNamedFramebufferfv(targets.second_bounce_framebuffer.id(), GL_COLOR, 0, zero);
}

void ComposePass::accumulate(int slot, const RenderContext& context, const GBuffer& gbuffer, GLuint direct,
                             const Indirect& indirect) {
  StageScope scope(context.timer, Stage::Compose);
  const Targets& targets = slots_.at(std::size_t(slot));
  glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffer.id());
  glViewport(0, 0, context.width, context.height);
  gbuffer.bind_for_reading();
  glBindTextureUnit(8, direct);
  glBindTextureUnit(11, indirect.light);
  glBindTextureUnit(12, indirect.vpls);
  glBindTextureUnit(14, indirect.near_field);
  glBindTextureUnit(15, indirect.near_field_second);
  glUseProgram(program_.id());
  const BounceWorld& world = context.scene.world();
  const float seen = world.transparent || world.camera_hidden ? 0.0f : 1.0f;
  glUniform3f(0, seen * world.background[0], seen * world.background[1], seen * world.background[2]);
  glUniform1f(1, world.transparent ? 0.0f : 1.0f);
  const GLuint environment = context.scene.texture_id(world.environment_texture);
  glBindTextureUnit(13, environment);
  glUniform1i(4, environment != 0 ? 1 : 0);
  glUniformMatrix3fv(5, 1, GL_FALSE, world.world_to_environment);
  const glm::mat4 clip_to_world = glm::inverse(context.view_projection);
  glUniformMatrix4fv(6, 1, GL_FALSE, &clip_to_world[0][0]);
  glUniform2f(7, float(context.width), float(context.height));
  glUniform1i(2, indirect.light != 0);
  glUniform1i(3, indirect.times_albedo ? 1 : 0);
  glUniform1i(8, indirect.near_field != 0);
  glUniform1i(9, indirect.near_field_second != 0);
  glEnable(GL_BLEND);
  for (GLuint aov = 0; aov < kComposedAovs; ++aov) {
    glBlendFunci(aov, GL_ONE, GL_ONE);
    glBlendEquationi(aov, aov == BOUNCE_AOV_DEPTH ? GL_MIN : GL_FUNC_ADD);
  }
  draw_fullscreen_triangle();
  for (const GLuint second_bounce : {indirect.second_bounce, indirect.near_field_second}) {
    if (second_bounce == 0) continue;
    glBindFramebuffer(GL_FRAMEBUFFER, targets.second_bounce_framebuffer.id());
    glBindTextureUnit(12, second_bounce);
    glUseProgram(add_times_albedo_.id());
    glBlendFunci(0, GL_ONE, GL_ONE);
    glBlendEquationi(0, GL_FUNC_ADD);
    draw_fullscreen_triangle();
  }
  glDisable(GL_BLEND);
}

void ComposePass::read(int slot, int samples, Frame& frame, int x, int y, Into into) {
  const Targets& targets = slots_.at(std::size_t(slot));
  std::vector<gl::TextureReadback::Image> images;
  std::vector<int> aovs;
  for (int aov = 0; aov < BOUNCE_AOV_COUNT; ++aov)
    if (frame.holds(aov)) {
      images.push_back({targets.textures[aov].id(), aov == BOUNCE_AOV_DEPTH ? 1 : 4});
      aovs.push_back(aov);
    }
  const float* texels = readback_.read(images, targets.width, targets.height);
  const std::size_t pixels = std::size_t(targets.width) * std::size_t(targets.height);
  const float scale = 1.0f / static_cast<float>(samples);
  // A tile at the frame's right or bottom edge may reach past it (Renderer::render's tiles): those texels stay out.
  const int columns = std::min(targets.width, frame.width - x), rows = std::min(targets.height, frame.height - y);
  parallel_for(std::size_t(rows), 0, 16, [&](std::size_t row) {
    const float* image = texels;
    for (std::size_t a = 0; a < aovs.size(); ++a) {
      const int aov = aovs[a], channels = bounce_aov_channels(aov), stride = images[a].components;
      const bool depth = aov == BOUNCE_AOV_DEPTH;
      const float* src = image + row * std::size_t(targets.width) * stride;
      float* dst = frame.aovs[aov].data() + ((std::size_t(y) + row) * frame.width + x) * channels;
      for (int col = 0; col < columns; ++col, src += stride, dst += channels)
        for (int c = 0; c < channels; ++c) {
          const float value = depth ? src[c] : src[c] * scale;
          if (into == Into::Replace)
            dst[c] = value;
          else
            dst[c] = depth ? std::min(dst[c], value) : dst[c] + value;
        }
      image += pixels * stride;
    }
  });
  readback_.release();
}

}  // namespace bounce
