#include "passes/blur/geometry_blur.h"

#include "gl/shader.h"

namespace bounce {

namespace {
constexpr GLuint kSourceUnit = 12;
}

GeometryBlur::GeometryBlur()
    : program_(gl::build_program(
          {{GL_VERTEX_SHADER, "common/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "blur/geometry_blur.frag"}})) {}

GLuint GeometryBlur::run(GLuint source, const GBuffer& gbuffer, int radius) {
  if (radius <= 0) return source;
  if (gbuffer.width != width_ || gbuffer.height != height_) {
    width_ = gbuffer.width;
    height_ = gbuffer.height;
    temp_ = gl::make_texture_2d(GL_RGBA32F, width_, height_);
    temp_target_ = gl::make_framebuffer({temp_.id()}, 0);
    result_ = gl::make_texture_2d(GL_RGBA32F, width_, height_);
    result_target_ = gl::make_framebuffer({result_.id()}, 0);
    gl::check("allocating the blur targets");
  }
  gbuffer.bind_for_reading();
  glViewport(0, 0, width_, height_);
  glUseProgram(program_.id());
  glUniform1i(1, radius);
  glBindFramebuffer(GL_FRAMEBUFFER, temp_target_.id());
  glBindTextureUnit(kSourceUnit, source);
  glUniform2i(0, 1, 0);
  draw_fullscreen_triangle();
  glBindFramebuffer(GL_FRAMEBUFFER, result_target_.id());
  glBindTextureUnit(kSourceUnit, temp_.id());
  glUniform2i(0, 0, 1);
  draw_fullscreen_triangle();
  return result_.id();
}

}  // namespace bounce
