#include "passes/shadows/shadow_pass.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/type_ptr.hpp>

#include "gl/shader.h"
#include "passes/light_views.h"
#include "radiometry.h"
#include "sampling.h"
#include "scene_data.h"

namespace bounce {

namespace {

constexpr double kShadowMemoryBudget = 1024.0 * 1024.0 * 1024.0;

ShadowKind kind_of(const BounceLight& light) {
  return light.cast_shadow ? static_cast<ShadowKind>(light_view_kind(light)) : kShadowNone;
}

gl::Texture make_shadow_texture(ShadowKind kind, int size) {
  gl::Texture texture = kind == kShadowCube ? gl::make_texture_cube(GL_DEPTH_COMPONENT32F, size)
                                            : gl::make_texture_2d(GL_DEPTH_COMPONENT32F, size, size);
  const GLuint id = texture.id();
  glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);  // 2x2 hardware PCF
  glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(id, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(id, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
  return texture;
}

// The diameter of the part of the light one sample stands for (sun: 2 tan of its half angle).
float sample_share_diameter(const BounceLight& light, const BounceSettings& settings) {
  float diameter = 0.0f;
  switch (light.type) {
    case BOUNCE_LIGHT_SUN:
      diameter = 2.0f * std::tan(0.5f * std::min(light.sun_angle, 3.0f));
      break;
    case BOUNCE_LIGHT_AREA_RECT:
    case BOUNCE_LIGHT_AREA_ELLIPSE:
      diameter = 2.0f * std::max(light.half_size[0], light.half_size[1]);
      break;
    case BOUNCE_LIGHT_AREA_TRIANGLE: {
      const auto corners = triangle_light_corners(light);
      diameter = std::max({glm::length(corners[1] - corners[0]), glm::length(corners[2] - corners[0]),
                           glm::length(corners[2] - corners[1])});
      break;
    }
    default:
      diameter = 2.0f * light.radius;
  }
  return diameter * settings.shadow_softness / std::sqrt(static_cast<float>(settings.samples));
}

}  // namespace

glm::vec3 light_shadow_origin(const BounceLight& light, uint32_t sample, uint32_t seed, uint32_t light_index,
                              float softness) {
  const glm::vec2 rotation(hash_to_unit(hash_combine(seed, 3 * light_index)),
                           hash_to_unit(hash_combine(seed, 3 * light_index + 1)));
  const glm::vec2 u = sample == 0 ? glm::vec2(0.5f) : r2_point(sample, rotation);
  const glm::vec3 centre = vec3_of(light.position);
  const glm::vec3 ax = vec3_of(light.axis_x), ay = vec3_of(light.axis_y), az = vec3_of(light.axis_z);
  switch (light.type) {
    case BOUNCE_LIGHT_SUN: {
      const float half_angle = 0.5f * light.sun_angle * softness;
      if (sample == 0 || half_angle <= 0.0f) return az;
      const float cos_theta = 1.0f - u.x * (1.0f - std::cos(half_angle));
      const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
      const float phi = 2.0f * kPi * u.y;
      return glm::normalize(cos_theta * az + sin_theta * (std::cos(phi) * ax + std::sin(phi) * ay));
    }
    case BOUNCE_LIGHT_AREA_RECT:
      return centre +
             softness * ((2.0f * u.x - 1.0f) * light.half_size[0] * ax + (2.0f * u.y - 1.0f) * light.half_size[1] * ay);
    case BOUNCE_LIGHT_AREA_ELLIPSE: {
      const glm::vec2 d = concentric_disk(u);
      return centre + softness * (d.x * light.half_size[0] * ax + d.y * light.half_size[1] * ay);
    }
    case BOUNCE_LIGHT_AREA_TRIANGLE: {  // around the centroid, shrunk by the softness
      const auto corners = triangle_light_corners(light);
      const glm::vec3 centroid = (corners[0] + corners[1] + corners[2]) / 3.0f;
      if (sample == 0) return centroid;
      return centroid + softness * (uniform_triangle_point(corners[0], corners[1], corners[2], u) - centroid);
    }
    default: {  // point, spot: uniform in the ball of the light's radius
      if (sample == 0 || light.radius <= 0.0f) return centre;
      const float z = 1.0f - 2.0f * u.x;
      const float r_xy = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const float phi = 2.0f * kPi * u.y;
      const float radius = light.radius * softness * std::cbrt(hash_to_unit(hash_combine(seed + sample, light_index)));
      return centre + radius * glm::vec3(r_xy * std::cos(phi), r_xy * std::sin(phi), z);
    }
  }
}

ShadowPass::ShadowPass()
    : program_(
          gl::build_program({{GL_VERTEX_SHADER, "shadows/shadow.vert"}, {GL_FRAGMENT_SHADER, "shadows/shadow.frag"}})) {
  GLuint id = 0;
  glCreateFramebuffers(1, &id);
  framebuffer_ = gl::Framebuffer(id);
  glNamedFramebufferDrawBuffer(id, GL_NONE);
  glNamedFramebufferReadBuffer(id, GL_NONE);
  // Samplers of both types must have a texture of their type bound, even when the light uses the other one.
  dummy_2d_ = make_shadow_texture(kShadowOrthographic, 1);
  dummy_cube_ = make_shadow_texture(kShadowCube, 1);
  // Units 9 and 10 read the same depth maps as raw depth, for the blocker search.
  GLuint sampler = 0;
  glCreateSamplers(1, &sampler);
  glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glSamplerParameteri(sampler, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  for (GLenum wrap : {GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R})
    glSamplerParameteri(sampler, wrap, GL_CLAMP_TO_EDGE);
  raw_depth_sampler_ = gl::Sampler(sampler);
  const float one = 1.0f;
  glClearTexImage(dummy_2d_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &one);
  glClearTexImage(dummy_cube_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &one);
}

void ShadowPass::trim(std::size_t light_count) {
  if (maps_.size() > light_count) maps_.resize(light_count);
}

void ShadowPass::prepare(const RenderContext& context, std::size_t index, const BounceLight& light, LightBlock& block) {
  glBindTextureUnit(6, dummy_2d_.id());
  glBindTextureUnit(7, dummy_cube_.id());
  const ShadowKind kind = context.scene.has_geometry() ? kind_of(light) : kShadowNone;
  const glm::vec3 origin = light_shadow_origin(light, context.sample, context.seed, static_cast<uint32_t>(index),
                                               context.settings.shadow_softness);
  std::memcpy(block.shadow_origin, &origin[0], sizeof(float) * 3);
  block.shadow_params[0] = static_cast<float>(kind);
  if (kind == kShadowNone) return;

  if (maps_.size() <= index) maps_.resize(index + 1);
  ShadowMap& map = maps_[index];
  const int faces = kind == kShadowCube ? 6 : 1;
  const double lights = static_cast<double>(std::max<std::size_t>(context.lights.size(), 1));
  const int size = size_within_budget(context.settings.shadow_map_size, 64, lights * faces, 4.0, kShadowMemoryBudget);

  const bool reuse = map.depth && map.kind == kind && map.size == size && map.origin == origin &&
                     map.geometry_version == context.scene.geometry_version() &&
                     std::memcmp(&map.light, &light, sizeof light) == 0;
  if (!reuse) {
    StageScope scope(context.timer, Stage::Shadows);
    if (!map.depth || map.kind != kind || map.size != size) {
      map.depth = make_shadow_texture(kind, size);
      const float far_depth = 1.0f;  // faces never rendered (behind an emitter) read as unoccluded
      glClearTexImage(map.depth.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, &far_depth);
      gl::check("allocating a shadow map");
    }
    map.kind = kind;
    map.size = size;
    map.origin = origin;
    map.geometry_version = context.scene.geometry_version();
    map.light = light;
    const LightViews views = light_views(light, origin, context.scene.bounds_min(), context.scene.bounds_max(), size);
    map.view_projection = views.view_projection[0];
    map.texel_factor = views.texel_factor;
    map.near_plane = views.near_plane;
    map.far_plane = views.far_plane;
    render(context, map, views.view_projection.data(), views.faces, views.skipped_face);
  }
  glBindTextureUnit(kind == kShadowCube ? 7 : 6, map.depth.id());
  glBindTextureUnit(kind == kShadowCube ? 10 : 9, map.depth.id());
  block.shadow_view_projection = map.view_projection;
  block.shadow_soft[0] = sample_share_diameter(light, context.settings);
  block.shadow_soft[1] = static_cast<float>(size);
  block.shadow_soft[2] = static_cast<float>(context.sample);
  block.shadow_params[1] = map.texel_factor;
  block.shadow_params[2] = map.near_plane;
  block.shadow_params[3] = map.far_plane;
}

void ShadowPass::render(const RenderContext& context, ShadowMap& map, const glm::mat4* face_view_projections, int faces,
                        int skipped_face) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
  glViewport(0, 0, map.size, map.size);
  glUseProgram(program_.id());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  for (int face = 0; face < faces; ++face) {
    if (face == skipped_face) continue;
    if (map.kind == kShadowCube)
      glNamedFramebufferTextureLayer(framebuffer_.id(), GL_DEPTH_ATTACHMENT, map.depth.id(), 0, face);
    else
      glNamedFramebufferTexture(framebuffer_.id(), GL_DEPTH_ATTACHMENT, map.depth.id(), 0);
    const float far_depth = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &far_depth);
    glUniformMatrix4fv(binding::kViewProjection, 1, GL_FALSE, glm::value_ptr(face_view_projections[face]));
    context.scene.draw();
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_DEPTH_TEST);
  gl::check("rendering a shadow map");
}

}  // namespace bounce
