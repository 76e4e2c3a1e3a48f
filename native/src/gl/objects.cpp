#include "gl/objects.h"

#include "error.h"

namespace bounce::gl {

void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }
void delete_query(GLuint id) { glDeleteQueries(1, &id); }
void delete_sampler(GLuint id) { glDeleteSamplers(1, &id); }

Buffer make_buffer(std::size_t bytes, const void* data, GLbitfield flags) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes == 0 ? 16 : bytes), data, flags);
  return Buffer(id);
}

void reserve_buffer(Buffer& buffer, std::size_t& capacity, std::size_t bytes) {
  if (!buffer || bytes > capacity) {
    capacity = bytes < 256 ? 256 : bytes + bytes / 2;
    buffer = make_buffer(capacity, nullptr);
  }
}

void upload_buffer(Buffer& buffer, std::size_t& capacity, std::size_t bytes, const void* data) {
  reserve_buffer(buffer, capacity, bytes);
  if (bytes) glNamedBufferSubData(buffer.id(), 0, static_cast<GLsizeiptr>(bytes), data);
}

Texture make_texture_2d(GLenum internal_format, int width, int height, int levels) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &id);
  glTextureStorage2D(id, levels, internal_format, width, height);
  glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST);
  glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, levels > 1 ? GL_LINEAR : GL_NEAREST);
  glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return Texture(id);
}

Texture make_texture_cube(GLenum internal_format, int size) {
  GLuint id = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &id);
  glTextureStorage2D(id, 1, internal_format, size, size);
  glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return Texture(id);
}

Framebuffer make_framebuffer(const std::vector<GLuint>& colour, GLuint depth, int layer) {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  Framebuffer framebuffer(id);
  std::vector<GLenum> draw_buffers;
  for (std::size_t i = 0; i < colour.size(); ++i) {
    const GLenum attachment = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i);
    if (layer >= 0)
      glNamedFramebufferTextureLayer(id, attachment, colour[i], 0, layer);
    else
      glNamedFramebufferTexture(id, attachment, colour[i], 0);
    draw_buffers.push_back(attachment);
  }
  if (depth) {
    if (layer >= 0)
      glNamedFramebufferTextureLayer(id, GL_DEPTH_ATTACHMENT, depth, 0, layer);
    else
      glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, depth, 0);
  }
  if (draw_buffers.empty())
    glNamedFramebufferDrawBuffer(id, GL_NONE);
  else
    glNamedFramebufferDrawBuffers(id, static_cast<GLsizei>(draw_buffers.size()), draw_buffers.data());
  const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    fail(BOUNCE_ERROR_GL, "framebuffer incomplete (status 0x" + std::to_string(status) + ")");
  return framebuffer;
}

void check(const char* what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  if (error == GL_OUT_OF_MEMORY)
    fail(BOUNCE_ERROR_GL,
         std::string(what) + ": out of GPU memory (lower the resolution, tile size or shadow map size)");
  fail(BOUNCE_ERROR_GL, std::string(what) + ": GL error 0x" + std::to_string(error));
}

}  // namespace bounce::gl
