// G-buffer pass. Shaders: shaders/gbuffer/gbuffer.vert, shaders/gbuffer/gbuffer.frag.
#pragma once

#include "gl/objects.h"
#include "passes/render_context.h"

namespace bounce {

struct GBuffer {
  gl::Texture albedo;            // RGBA16F: albedo, coverage
  gl::Texture normal;            // RGBA16F: shading normal
  gl::Texture position;          // RGBA32F: world position, view depth
  gl::Texture emission;          // RGBA16F
  gl::Texture geometric_normal;  // RGBA16F
  gl::Texture depth;             // DEPTH32F
  gl::Framebuffer framebuffer;
  int width = 0, height = 0;

  void bind_for_reading() const;  // texture units 1-5, as declared in the lighting shaders
};

class GBufferPass {
 public:
  GBufferPass();
  void execute(const RenderContext& context);
  const GBuffer& gbuffer() const { return gbuffer_; }

 private:
  void resize(int width, int height);
  gl::Program program_;
  GBuffer gbuffer_;
};

}  // namespace bounce
