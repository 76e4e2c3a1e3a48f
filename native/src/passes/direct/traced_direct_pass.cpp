#include "passes/direct/traced_direct_pass.h"

#include <glm/geometric.hpp>

#include "common/parallel.h"
#include "cpu/camera_ray.h"
#include "cpu/direct_light.h"
#include "cpu/near_field.h"
#include "cpu/random.h"
#include "error.h"
#include "radiometry.h"

namespace bounce {
namespace {

constexpr uint64_t kTracedDirect = 31;  // random stream of the shadow rays
constexpr uint64_t kNearField = 32;     // of the near field's rays
constexpr uint64_t kUnseen = 33;        // of the rays that light what the near field's rays meet unseen

}  // namespace

void TracedDirectPass::execute(const RenderContext& context, const GBuffer& gbuffer, const cpu::CpuScene& scene,
                               const SceneLights& scene_lights, NearFieldRays near_field) {
  const int width = context.width, height = context.height;
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  const auto& lights = context.lights;
  // Shadow rays leave from the surface pushed along the shading normal (on the geometric normal's side, so off
  // the surface); the light itself is evaluated at the surface point, as the rasterizer does.
  const cpu::ShadowRays rays{scene.bvh(), scene.ray_offset(), 1, scene.opaque(), context.settings.shadow_softness};
  const cpu::WorldStrategies world{scene_lights, context.settings.world_lights};
  const glm::vec4 *position = nullptr, *normal = nullptr, *albedo = nullptr, *geometric_normal = nullptr;
  // Sets out[i] to light(x, rng, progression, i) for each covered pixel i, with its surface x, one random stream
  // per image pixel, sample and `stream`, and the pixel's place in the samples: tiles and the untiled image draw
  // the same rays.
  const auto each_pixel = [&](std::vector<glm::vec4>& out, uint64_t stream, const auto& light) {
    out.assign(pixels, glm::vec4(0.0f));
    if (lights.empty() || scene.triangle_count() == 0) return;
    parallel_for(std::size_t(height), 0, 1, [&](std::size_t row) {
      for (std::size_t i = row * std::size_t(width); i < (row + 1) * std::size_t(width); ++i) {
        if (albedo[i].a == 0.0f) continue;
        const cpu::Surface x{glm::vec3(position[i]),
                             glm::normalize(glm::vec3(geometric_normal[i])),
                             glm::normalize(glm::vec3(normal[i])),
                             glm::vec3(albedo[i]),
                             {}};
        const uint64_t pixel = (uint64_t(uint32_t(context.tile_origin.y) + uint32_t(row)) << 32) |
                               uint32_t(context.tile_origin.x + int(i - row * std::size_t(width)));
        cpu::Rng rng(context.seed, stream ^ (uint64_t(context.sample) << 8), pixel);
        const cpu::Progression progression{cpu::mix(context.seed ^ cpu::mix(stream)) ^ pixel, context.sample};
        out[i] = light(x, rng, progression, i);
      }
    });
  };
  {
    StageScope scope(context.timer, Stage::TracedDirect);
    if (width_ != width || height_ != height) {
      direct_ = gl::make_texture_2d(GL_RGBA32F, width, height);
      near_field_ = gl::make_texture_2d(GL_RGBA32F, width, height);
      near_field_reflectance_ = gl::make_texture_2d(GL_RGBA32F, width, height);
      near_field_source_ = gl::make_texture_2d(GL_R32I, width, height);
      near_field_unseen_ = gl::make_texture_2d(GL_RGBA32F, width, height);
      width_ = width;
      height_ = height;
    }
    const auto* texels = reinterpret_cast<const glm::vec4*>(gbuffer_readback_.read({{gbuffer.position.id(), 4},
                                                                                    {gbuffer.normal.id(), 4},
                                                                                    {gbuffer.albedo.id(), 4},
                                                                                    {gbuffer.geometric_normal.id(), 4}},
                                                                                   width, height));
    position = texels;
    normal = texels + pixels;
    albedo = texels + 2 * pixels;
    geometric_normal = texels + 3 * pixels;
    each_pixel(light_, kTracedDirect,
               [&](const cpu::Surface& x, cpu::Rng& rng, const cpu::Progression& progression, std::size_t) {
                 return glm::vec4(
                     x.albedo / kPi *
                         cpu::direct_irradiance(lights, x.position, x.shading_normal, rays, rng, &world, &progression),
                     0.0f);
               });
    glTextureSubImage2D(direct_.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, light_.data());
  }
  if (near_field.clamp > 0.0f) {
    StageScope scope(context.timer, Stage::NearField);
    if (near_field.second_bounce) {
      near_reflectance_.assign(pixels, glm::vec4(0.0f));
      near_source_.assign(pixels, -1);
      near_unseen_.assign(pixels, glm::vec4(0.0f));
    }
    const glm::dmat4 world_to_clip(context.view_projection);
    const cpu::UnseenFirstBounce unseen(
        near_field.second_bounce ? near_field.first_bounce_vpls : std::span<const cpu::Vpl>{}, near_field.clamp);
    const auto seen = [&](std::size_t j) {
      return albedo[j].a != 0.0f
                 ? std::optional<cpu::SeenSurface>({glm::vec3(position[j]), glm::normalize(glm::vec3(normal[j]))})
                 : std::nullopt;
    };
    each_pixel(near_light_, kNearField,
               [&](const cpu::Surface& x, cpu::Rng& rng, const cpu::Progression& progression, std::size_t i) {
                 const cpu::NearField y =
                     cpu::near_field(scene, x, lights, rays, world, near_field.clamp, progression, rng);
                 if (near_field.second_bounce && y.normal != glm::vec3(0.0f)) {
                   const std::optional<std::size_t> j = cpu::first_bounce_pixel(
                       y, i, cpu::image_point(world_to_clip, glm::dvec3(y.position), width, height), width, height,
                       near_field.clamp, seen);
                   if (j) {
                     near_reflectance_[i] = glm::vec4(y.reflectance, 0.0f);
                     near_source_[i] = int32_t(*j);
                   } else if (!near_field.first_bounce_vpls.empty()) {
                     const cpu::Progression own{cpu::mix(progression.key ^ cpu::mix(kUnseen)), progression.sample};
                     near_unseen_[i] =
                         glm::vec4(y.reflectance / kPi * unseen.at(scene, y, lights, rays, world, own, rng), 0.0f);
                   }
                 }
                 return glm::vec4(y.irradiance / kPi, 0.0f);
               });
    glTextureSubImage2D(near_field_.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, near_light_.data());
    if (near_field.second_bounce) {
      glTextureSubImage2D(near_field_reflectance_.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT,
                          near_reflectance_.data());
      glTextureSubImage2D(near_field_source_.id(), 0, 0, 0, width, height, GL_RED_INTEGER, GL_INT, near_source_.data());
      glTextureSubImage2D(near_field_unseen_.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, near_unseen_.data());
    }
  }
  gbuffer_readback_.release();
  gl::check("uploading the ray-traced direct light");
}

}  // namespace bounce
