// G-buffer pass. Shaders: shaders/gbuffer/gbuffer.vert, shaders/gbuffer/gbuffer.frag.
#pragma once

#include <span>

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

// Bytes per texel of a GBuffer: albedo, normal, emission and geometric normal RGBA16F, position RGBA32F, depth 32F.
constexpr int kGBufferBytesPerTexel = 4 * 8 + 16 + 4;
GBuffer make_gbuffer(int width, int height);

// One view drawn into a G-buffer: the camera's, or one face of a light's reflective shadow map.
struct GBufferView {
  glm::mat4 view_projection;
  glm::mat4 world_to_view;  // its -z is the depth stored in position.w
  glm::vec3 eye;            // perspective: normals are flipped towards it
  glm::vec3 forward;        // orthographic: normals are flipped against it
  bool orthographic;
  glm::ivec4 viewport;  // x, y, width, height in the target
};

class GBufferPass {
 public:
  GBufferPass();
  void execute(const RenderContext& context);  // the camera's view into gbuffer()
  // Clears `target` and draws every view into its viewport.
  void render(GBuffer& target, std::span<const GBufferView> views, const GpuScene& scene) const;
  const GBuffer& gbuffer() const { return gbuffer_; }

 private:
  gl::Program program_;
  GBuffer gbuffer_;
};

}  // namespace bounce
