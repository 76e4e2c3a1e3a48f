#include "gl/objects.h"

#include <algorithm>
#include <cstdio>

#include "common/fault_injection.h"
#include "error.h"

namespace bounce::gl {

namespace {

[[noreturn]] void fail_out_of_gpu_memory(const std::string& what) {
  fail(BOUNCE_ERROR_GL, what + ": out of GPU memory (lower the resolution, tile size or shadow map size)");
}

}  // namespace

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

void Readback::read(GLuint source, std::size_t bytes, void* out) {
  if (bytes == 0) return;
  if (!staging_ || bytes > capacity_) {
    staging_ = make_buffer(bytes, nullptr, GL_CLIENT_STORAGE_BIT);
    capacity_ = bytes;
  }
  glCopyNamedBufferSubData(source, staging_.id(), 0, 0, static_cast<GLsizeiptr>(bytes));
  glGetNamedBufferSubData(staging_.id(), 0, static_cast<GLsizeiptr>(bytes), out);
}

const float* TextureReadback::read(const std::vector<Image>& images, int width, int height) {
  release();
  const std::size_t texels = std::size_t(width) * std::size_t(height);
  std::size_t bytes = 0;
  for (const Image& image : images) bytes += texels * std::size_t(image.components) * sizeof(float);
  if (bytes == 0) return nullptr;
  if (!buffer_ || bytes > capacity_) {
    buffer_ = make_buffer(bytes, nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT);
    capacity_ = bytes;
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer_.id());
  std::size_t offset = 0;
  for (const Image& image : images) {
    const std::size_t image_bytes = texels * std::size_t(image.components) * sizeof(float);
    glGetTextureImage(image.texture, 0, image.components == 1 ? GL_RED : GL_RGBA, GL_FLOAT,
                      static_cast<GLsizei>(image_bytes), reinterpret_cast<void*>(offset));
    offset += image_bytes;
  }
  glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  const void* mapped = glMapNamedBufferRange(buffer_.id(), 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT);
  if (!mapped) fail(BOUNCE_ERROR_GL, "mapping " + std::to_string(bytes) + " bytes read back from the GPU failed");
  mapped_ = true;
  return static_cast<const float*>(mapped);
}

void TextureReadback::release() {
  if (mapped_) glUnmapNamedBuffer(buffer_.id());
  mapped_ = false;
}

Texture make_texture_2d(GLenum internal_format, int width, int height, int levels) {
  if (fault_injected("gl-oom"))
    fail_out_of_gpu_memory("allocating a " + std::to_string(width) + "x" + std::to_string(height) + " texture");
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
  if (fault_injected("gl-oom")) fail_out_of_gpu_memory("allocating a cube map of " + std::to_string(size) + " pixels");
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
    fail(BOUNCE_ERROR_GL, "framebuffer incomplete (status " + error_name(status) + ")");
  return framebuffer;
}

void dispatch_linear(uint64_t invocations, uint32_t local_size) {
  constexpr uint64_t kMaxGroupsPerDimension = 65535;
  const uint64_t groups = (invocations + local_size - 1) / local_size;
  if (groups == 0) return;
  const uint64_t columns = std::min(groups, kMaxGroupsPerDimension);
  const uint64_t rows = (groups + columns - 1) / columns;
  if (rows > kMaxGroupsPerDimension)
    fail(BOUNCE_ERROR_OUT_OF_MEMORY, "a compute dispatch of " + std::to_string(invocations) + " invocations");
  glDispatchCompute(static_cast<GLuint>(columns), static_cast<GLuint>(rows), 1);
}

std::string error_name(GLenum code) {
  const char* name = nullptr;
  switch (code) {
    case GL_INVALID_ENUM:
      name = "GL_INVALID_ENUM";
      break;
    case GL_INVALID_VALUE:
      name = "GL_INVALID_VALUE";
      break;
    case GL_INVALID_OPERATION:
      name = "GL_INVALID_OPERATION";
      break;
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      name = "GL_INVALID_FRAMEBUFFER_OPERATION";
      break;
    case GL_OUT_OF_MEMORY:
      name = "GL_OUT_OF_MEMORY";
      break;
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
      name = "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
      break;
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
      name = "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
      break;
    case GL_FRAMEBUFFER_UNSUPPORTED:
      name = "GL_FRAMEBUFFER_UNSUPPORTED";
      break;
    default:
      break;
  }
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%04x", static_cast<unsigned>(code));
  return name ? std::string(name) + " (" + hex + ")" : std::string(hex);
}

void check(const char* what) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  if (error == GL_OUT_OF_MEMORY) fail_out_of_gpu_memory(what);
  fail(BOUNCE_ERROR_GL, std::string(what) + ": GL error " + error_name(error));
}

}  // namespace bounce::gl
