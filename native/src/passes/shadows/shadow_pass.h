// Shadow maps, one per shadow-casting light, kept while neither the light's sample point nor the geometry
// changes. Shaders: shaders/shadows/shadow.vert, shaders/shadows/shadow.frag.
//
// Kinds (passes/light_views.h): sun - orthographic, fitted to the scene's bounding sphere; spot - perspective
// over the cone (a cube when the cone is wider than 150 degrees); point and area - a cube map in the light's
// frame (area and spot lights skip the face behind them).
//
// Soft shadows (a documented approximation): sample s renders the map from a point drawn uniformly on the
// light (area: its rectangle or ellipse; point/spot: the ball of its radius; sun: the cone of its angular
// diameter), scaled by settings.shadow_softness. The direct pass multiplies the exact unshadowed irradiance by
// this visibility, so over the samples the shadow converges to the light-averaged visibility, which is the
// exact answer as the light gets small (and exact for any size where it is fully visible or fully hidden).
// Sample 0 uses the light's centre. So that few samples do not show as stacked hard shadows, each lookup is
// also filtered (percentage-closer, with a blocker search as in PCSS) over the penumbra of the sample's share
// of the light, whose diameter is the light's divided by sqrt(samples): the filter vanishes as samples grow.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "gl/objects.h"
#include "passes/render_context.h"

namespace bounce {

// std140 mirror of shaders/common/lights.glsl `LightBlock`.
struct LightBlock {
  float position_type[4];
  float axis_x[4];
  float axis_y[4];
  float axis_z[4];
  float intensity[4];
  float shape[4];
  float spot_sun[4];
  float triangle[4];
  float shadow_origin[4];
  glm::mat4 shadow_view_projection;
  float shadow_params[4];
  float shadow_soft[4];
};

// The shaders' SHADOW_* kinds: a light's view kind (passes/light_views.h), or none.
enum ShadowKind { kShadowNone = 0, kShadowOrthographic = 1, kShadowPerspective = 2, kShadowCube = 3 };

class ShadowPass {
 public:
  ShadowPass();
  // Renders (or reuses) light `index`'s map for this sample, binds it to units 6 (2D) and 7 (cube), and fills
  // the shadow fields of `block`.
  void prepare(const RenderContext& context, std::size_t index, const BounceLight& light, LightBlock& block);
  void trim(std::size_t light_count);  // frees the maps of lights that no longer exist

 private:
  struct ShadowMap {
    gl::Texture depth;
    ShadowKind kind = kShadowNone;
    int size = 0;
    glm::vec3 origin{0.0f};
    uint64_t geometry_version = 0;
    BounceLight light{};
    glm::mat4 view_projection{1.0f};
    float texel_factor = 0.0f, near_plane = 0.0f, far_plane = 0.0f;
  };

  void render(const RenderContext& context, ShadowMap& map, const glm::mat4* face_view_projections, int faces,
              int skipped_face);

  gl::Program program_;
  gl::Framebuffer framebuffer_;
  gl::Texture dummy_2d_, dummy_cube_;
  gl::Sampler raw_depth_sampler_;
  std::vector<ShadowMap> maps_;
};

// The point of the light sample `sample` sees shadows from (world position, or for a sun the unit direction
// towards it). Exposed for tests.
glm::vec3 light_shadow_origin(const BounceLight& light, uint32_t sample, uint32_t seed, uint32_t light_index,
                              float softness);

}  // namespace bounce
