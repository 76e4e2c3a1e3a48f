#include "passes/direct/traced_direct_pass.h"

#include <glm/geometric.hpp>

#include "common/parallel.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"
#include "error.h"
#include "radiometry.h"

namespace bounce {
namespace {

constexpr uint64_t kTracedDirect = 31;  // random stream of the shadow rays

}  // namespace

void TracedDirectPass::execute(const RenderContext& context, const GBuffer& gbuffer, const cpu::CpuScene& scene,
                               const SceneLights& scene_lights) {
  StageScope scope(context.timer, Stage::TracedDirect);
  const int width = context.width, height = context.height;
  if (width_ != width || height_ != height) {
    direct_ = gl::make_texture_2d(GL_RGBA32F, width, height);
    width_ = width;
    height_ = height;
  }
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  const auto* texels = reinterpret_cast<const glm::vec4*>(gbuffer_readback_.read(
      {{gbuffer.position.id(), 4}, {gbuffer.normal.id(), 4}, {gbuffer.albedo.id(), 4}}, width, height));
  const glm::vec4 *position = texels, *normal = texels + pixels, *albedo = texels + 2 * pixels;
  light_.assign(pixels, glm::vec4(0.0f));
  const auto& lights = context.lights;
  // Shadow rays leave from the surface pushed along the shading normal (on the geometric normal's side, so off
  // the surface); the light itself is evaluated at the surface point, as the rasterizer does.
  const cpu::ShadowRays rays{scene.bvh(), scene.ray_offset(), 1, scene.opaque(), context.settings.shadow_softness};
  const cpu::WorldStrategies world{scene_lights, context.settings.world_lights};
  if (!lights.empty() && scene.triangle_count() > 0) {
    parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
      for (std::size_t i = row * std::size_t(width); i < (row + 1) * std::size_t(width); ++i) {
        if (albedo[i].a == 0.0f) continue;
        const glm::vec3 n = glm::normalize(glm::vec3(normal[i])), y = glm::vec3(position[i]);
        // One stream per image pixel and sample: tiles and the untiled image draw the same rays.
        const uint64_t pixel = (uint64_t(uint32_t(context.tile_origin.y) + uint32_t(row)) << 32) |
                               uint32_t(context.tile_origin.x + int(i - row * std::size_t(width)));
        cpu::Rng rng(context.seed, kTracedDirect ^ (uint64_t(context.sample) << 8), pixel);
        const glm::vec3 e = cpu::direct_irradiance(lights, y, n, rays, rng, &world);
        light_[i] = glm::vec4(glm::vec3(albedo[i]) / kPi * e, 0.0f);
      }
    });
  }
  gbuffer_readback_.release();
  glTextureSubImage2D(direct_.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, light_.data());
  gl::check("uploading the ray-traced direct light");
}

}  // namespace bounce
