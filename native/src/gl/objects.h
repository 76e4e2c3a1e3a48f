// Owning wrappers of GL object names (render thread only) and the few helpers every pass uses.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace bounce::gl {

template <void (*Delete)(GLuint)>
class Name {
 public:
  Name() = default;
  explicit Name(GLuint id) : id_(id) {}
  ~Name() { reset(); }
  Name(Name&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Name& operator=(Name&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, 0);
    }
    return *this;
  }
  Name(const Name&) = delete;
  Name& operator=(const Name&) = delete;
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void delete_buffer(GLuint id);
void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_program(GLuint id);
void delete_query(GLuint id);
void delete_sampler(GLuint id);

using Buffer = Name<delete_buffer>;
using Texture = Name<delete_texture>;
using Framebuffer = Name<delete_framebuffer>;
using VertexArray = Name<delete_vertex_array>;
using Program = Name<delete_program>;
using Query = Name<delete_query>;
using Sampler = Name<delete_sampler>;

Buffer make_buffer(std::size_t bytes, const void* data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
// Grows (never shrinks) `buffer` to hold `bytes`; `capacity` tracks its size. Contents are lost when it grows.
void reserve_buffer(Buffer& buffer, std::size_t& capacity, std::size_t bytes);
// reserve_buffer, then uploads `bytes` of `data`.
void upload_buffer(Buffer& buffer, std::size_t& capacity, std::size_t bytes, const void* data);
// Reads what the GPU wrote into a buffer through a staging buffer of its own. Reading the GPU's working buffer
// itself makes NVIDIA's driver move it to host memory ("copied/moved from VIDEO memory to HOST memory"), after
// which, on an H200 (driver 580.159), the indirect draw it fed made nothing: Forward Light Cuts' divergent
// pipeline generated no VPL after a render's first sample.
class Readback {
 public:
  void read(GLuint source, std::size_t bytes, void* out);

 private:
  Buffer staging_;
  std::size_t capacity_ = 0;
};

// Reads several float textures of one size back at once: every read is queued into a pixel-pack buffer of its
// own before the host waits, so it waits for the GPU once instead of once a texture, and reads the texels where
// the driver put them (mapped) instead of copying each image into memory of its own.
class TextureReadback {
 public:
  struct Image {
    GLuint texture;
    int components;  // 4: read as GL_RGBA, 1: as GL_RED; floats either way
  };
  // The texels of `images` (each width x height), one image after another, rows bottom first; valid until
  // release() or the next read().
  const float* read(const std::vector<Image>& images, int width, int height);
  void release();

 private:
  Buffer buffer_;
  std::size_t capacity_ = 0;
  bool mapped_ = false;
};

Texture make_texture_2d(GLenum internal_format, int width, int height, int levels = 1);
Texture make_texture_cube(GLenum internal_format, int size);
Framebuffer make_framebuffer(const std::vector<GLuint>& colour, GLuint depth, int layer = -1);

// Runs the bound compute program over `invocations` invocations of `local_size`-wide work groups. GL promises
// only 65,535 groups per dimension (Mesa refuses more), so large counts spread over rows of a 2D grid: shaders
// number their invocations with linear_invocation() of shaders/common/dispatch.glsl and skip those past the count.
void dispatch_linear(uint64_t invocations, uint32_t local_size);

// "GL_INVALID_VALUE (0x0501)": a GL error or framebuffer status by name and code (just the code when unknown).
std::string error_name(GLenum code);
// Raises Error(BOUNCE_ERROR_GL) naming `what` if GL reports an error (out of memory included).
void check(const char* what);

}  // namespace bounce::gl
