#include "cpu/direct_light.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/vec2.hpp>

#include "cpu/lambert.h"
#include "radiometry.h"
#include "sampling.h"
#include "scene_data.h"

namespace bounce::cpu {
namespace {

float smoothstep(float edge0, float edge1, float x) {
  const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

int grid_side(int samples, int dimensions) {
  int k = 1;
  while (dimensions == 2 ? k * k < samples : k * k * k < samples) ++k;
  return k;
}

// The world's directions' items among a Progression's scrambles (the lights' are their indices).
constexpr uint64_t kWorldDirections = ~uint64_t(1), kCosineDirections = ~uint64_t(0), kGuidedDirections = ~uint64_t(2);

// The rays of one query.
struct ShadingContext {
  const embree::Scene& bvh;
  const embree::Scene::HitFilter& counts;
  float offset;
  int samples;
  float softness;
  glm::uvec3 scramble;  // of the sequence's points (Progression)
  uint32_t sample;      // the query takes its `count` points from sample x count on

  glm::vec2 point2(int j, int count) const {
    return sobol_point(sample * uint32_t(count) + uint32_t(j), glm::uvec2(scramble));
  }
  glm::vec3 point3(int j, int count) const { return sobol_point(sample * uint32_t(count) + uint32_t(j), scramble); }

  // Whether the segment from y (pushed off its surface along n) to `target` is free.
  bool visible(glm::vec3 y, glm::vec3 n, glm::vec3 target) const {
    const glm::vec3 origin = y + n * offset;
    const glm::vec3 to_target = target - origin;
    const float distance = glm::length(to_target);
    if (distance <= offset) return true;
    return !bvh.occluded(origin, to_target / distance, 0.0f, distance - offset, counts);
  }
  bool visible_direction(glm::vec3 y, glm::vec3 n, glm::vec3 dir) const {
    return !bvh.occluded(y + n * offset, dir, 0.0f, std::numeric_limits<float>::infinity(), counts);
  }
};

// Point and spot: lights.glsl's unshadowed irradiance I cos / (d^2 + r^2) (times the cone), times the visible
// fraction of the ball of radius r among its points above y's horizon (the GPU's shadow_visibility: the part below
// cannot reach y and carries no information).
glm::vec3 point_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const glm::vec3 centre = glm::make_vec3(light.position);
  const glm::vec3 to_light = centre - y;
  const float d2 = glm::dot(to_light, to_light);
  const glm::vec3 l = to_light / std::sqrt(std::max(d2, 1e-30f));
  const float r = light.radius * context.softness;  // the ball the shadows are seen from
  float falloff = std::max(glm::dot(n, l), 0.0f) / (d2 + light.radius * light.radius);
  if (light.type == BOUNCE_LIGHT_SPOT) falloff *= spot_attenuation(light, -l);
  const glm::vec3 unshadowed = glm::make_vec3(light.intensity) * falloff;
  if (!(falloff > 0.0f) || !light.cast_shadow) return unshadowed;
  if (r <= 0.0f) return context.visible(y, n, centre) ? unshadowed : glm::vec3(0.0f);
  const int k = grid_side(context.samples, 3), count = k * k * k;
  int above = 0, seen = 0;
  for (int j = 0; j < count; ++j) {
    const glm::vec3 u = context.point3(j, count);
    const float cos_theta = 1.0f - 2.0f * u.y;
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * u.z;
    const glm::vec3 p =
        centre + r * std::cbrt(u.x) * glm::vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
    if (glm::dot(n, p - y) <= 0.0f) continue;
    ++above;
    if (context.visible(y, n, p)) ++seen;
  }
  if (above == 0) return context.visible(y, n, centre) ? unshadowed : glm::vec3(0.0f);
  return unshadowed * (float(seen) / float(above));
}

// Sun: E cos toward axis_z, times the visible fraction of its disk (directions uniform in the cone of half the
// angular diameter) among the directions above y's horizon.
glm::vec3 sun_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const glm::vec3 z = glm::make_vec3(light.axis_z), x = glm::make_vec3(light.axis_x), w = glm::make_vec3(light.axis_y);
  const float cos_n = glm::dot(n, z);
  const glm::vec3 unshadowed = glm::make_vec3(light.intensity) * std::max(cos_n, 0.0f);
  if (!(cos_n > 0.0f) || !light.cast_shadow) return unshadowed;
  const float angle = light.sun_angle * context.softness;
  const float cos_max = std::cos(0.5f * angle);
  if (angle <= 0.0f) return context.visible_direction(y, n, z) ? unshadowed : glm::vec3(0.0f);
  const int k = grid_side(context.samples, 2), count = k * k;
  int above = 0, seen = 0;
  for (int j = 0; j < count; ++j) {
    const glm::vec2 u = context.point2(j, count);
    const float cos_theta = 1.0f - u.x * (1.0f - cos_max);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
    const float phi = 2.0f * kPi * u.y;
    const glm::vec3 dir = glm::normalize(cos_theta * z + sin_theta * (std::cos(phi) * x + std::sin(phi) * w));
    if (glm::dot(n, dir) <= 0.0f) continue;
    ++above;
    if (context.visible_direction(y, n, dir)) ++seen;
  }
  if (above == 0) return context.visible_direction(y, n, z) ? unshadowed : glm::vec3(0.0f);
  return unshadowed * (float(seen) / float(above));
}

// Whether y lies in a triangle light's plane (lights.glsl's tolerance): an emissive surface does not light itself,
// while Lambert's formula gives there the limit from above, pi L.
bool on_own_plane(const BounceLight& light, glm::vec3 y) {
  const float size =
      std::hypot(light.triangle[0], light.triangle[1]) + std::hypot(light.triangle[2], light.triangle[3]);
  return std::abs(glm::dot(y - glm::make_vec3(light.position), glm::make_vec3(light.axis_z))) <= 1e-4f * size;
}

// Area: lights.glsl's unshadowed irradiance, L times Lambert's polygon formula over the emitter clipped to y's
// horizon (the shaders' own code: lambert.h), times the visible fraction of the emitter's points above that
// horizon (stratified, seen from the light shrunk by the softness), as the shadow maps see it: exact wherever the
// whole light is seen or hidden, so only penumbrae are estimated (they converge to the light-averaged
// visibility, exact for small lights). Only the side facing -axis_z emits, but both sides of a triangle.
glm::vec3 area_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, ShadingContext& context) {
  const bool triangle = light.type == BOUNCE_LIGHT_AREA_TRIANGLE;
  const auto corners = triangle ? triangle_light_corners(light) : std::array<glm::vec3, 3>{};
  const glm::vec3 c = triangle ? (corners[0] + corners[1] + corners[2]) / 3.0f : glm::make_vec3(light.position);
  if (!triangle && glm::dot(y - c, -glm::make_vec3(light.axis_z)) <= 0.0f) return glm::vec3(0.0f);
  if (triangle && on_own_plane(light, y)) return glm::vec3(0.0f);
  const glm::vec3 u = glm::make_vec3(light.axis_x) * light.half_size[0],
                  v = glm::make_vec3(light.axis_y) * light.half_size[1];
  const bool rect = light.type == BOUNCE_LIGHT_AREA_RECT;
  glm::vec3 polygon[lambert::MAX_POLYGON], clipped[lambert::MAX_POLYGON];
  int corner_count = 3;
  if (triangle)
    for (int i = 0; i < 3; ++i) polygon[i] = corners[i] - y;
  else
    corner_count = lambert::emitter_polygon(c - y, u, v, rect, polygon);
  const int clipped_count = lambert::clip_to_horizon(polygon, corner_count, n, clipped);
  if (clipped_count < 3) return glm::vec3(0.0f);
  const glm::vec3 unshadowed =
      glm::make_vec3(light.intensity) * lambert::polygon_projected_solid_angle(clipped, clipped_count, n);
  if (!light.cast_shadow) return unshadowed;
  const int k = grid_side(context.samples, 2), count = k * k;
  int above = 0, seen = 0;
  for (int j = 0; j < count; ++j) {
    const glm::vec2 st = context.point2(j, count);
    glm::vec3 p;
    if (triangle) {
      p = c + context.softness * (uniform_triangle_point(corners[0], corners[1], corners[2], st) - c);
    } else {
      const glm::vec2 q = rect ? 2.0f * st - 1.0f : concentric_disk(st);
      p = c + context.softness * (q.x * u + q.y * v);
    }
    if (glm::dot(n, p - y) <= 0.0f) continue;
    ++above;
    if (context.visible(y, n, p)) ++seen;
  }
  if (above == 0) return context.visible(y, n, c) ? unshadowed : glm::vec3(0.0f);
  return unshadowed * (float(seen) / float(above));
}

// The scramble of light `light`'s points: the progression's, else drawn from `rng`.
glm::uvec3 sequence_scramble(const Progression* progression, uint64_t light, Rng& rng) {
  return progression ? progression->scramble(light) : glm::uvec3(rng.next_bits(), rng.next_bits(), rng.next_bits());
}

glm::vec3 shadowed_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, const ShadowRays& rays,
                              glm::uvec3 scramble, uint32_t sample) {
  ShadingContext context{rays.bvh, rays.counts, rays.offset, std::max(rays.samples, 1), std::max(rays.softness, 0.0f),
                         scramble, sample};
  switch (light.type) {
    case BOUNCE_LIGHT_POINT:
    case BOUNCE_LIGHT_SPOT:
      return point_irradiance(light, y, n, context);
    case BOUNCE_LIGHT_SUN:
      return sun_irradiance(light, y, n, context);
    default:
      return area_irradiance(light, y, n, context);
  }
}

}  // namespace

float spot_attenuation(const BounceLight& light, glm::vec3 from_light) {
  const float cos_phi = glm::dot(from_light, -glm::make_vec3(light.axis_z));
  const float cos_half = std::cos(light.spot_half_angle);
  if (cos_phi <= cos_half) return 0.0f;
  const float smooth_width = (1.0f - cos_half) * light.spot_blend;
  const float factor = smooth_width > 0.0f ? smoothstep(0.0f, smooth_width, cos_phi - cos_half) : 1.0f;
  return light.spot_cos_falloff != 0 ? factor * cos_phi : factor;
}

glm::vec3 light_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, const ShadowRays& rays, Rng& rng) {
  return shadowed_irradiance(light, y, n, rays, sequence_scramble(nullptr, 0, rng), 0);
}

glm::vec3 direct_irradiance(std::span<const BounceLight> lights, glm::vec3 y, glm::vec3 n, const ShadowRays& rays,
                            Rng& rng, const WorldStrategies* world, const Progression* progression) {
  glm::vec3 sum(0.0f);
  const uint32_t sample = progression ? progression->sample : 0;
  const std::size_t first = world ? world->lights.lamp_count() : lights.size(),
                    last = world ? first + world->lights.world_count() : first;
  for (std::size_t i = 0; i < lights.size(); ++i)
    if (i < first || i >= last)
      sum += shadowed_irradiance(lights[i], y, n, rays, sequence_scramble(progression, i, rng), sample);
  if (!world) return sum;
  const int drawn = int(last - first), cosine = std::max(world->cosine, 0);
  SkyGuide* const guide = world->guide;
  const uint32_t side = progression ? uint32_t(progression->key & 1u) : 0u;  // SkyGuide: the sequences' side
  const int guided = guide && guide->guides(side, y) ? cosine : 0;
  // The power heuristic's terms K p(w) of the three strategies toward w.
  const auto terms = [&](glm::vec3 w, float table_pdf) {
    return glm::vec3(float(drawn) * table_pdf, float(cosine) * std::max(glm::dot(n, w), 0.0f) / kPi,
                     guided > 0 ? float(guided) * guide->pdf(side, y, w) : 0.0f);
  };
  // With the power heuristic a direction adds at most L pi / (2 K_c): the guide learns its share of that.
  const float most = world->lights.world_peak() * kPi / (2.0f * float(std::max(cosine, 1)));
  // L cos / (K_s p_s), weighted by (K_s p_s)^2 over the sum of the terms squared.
  const auto add = [&](glm::vec3 w, glm::vec3 radiance, float cos_n, glm::vec3 t, float own) {
    const glm::vec3 light = radiance * (cos_n * own / glm::dot(t, t));
    sum += light;
    if (guide && most > 0.0f) guide->learn(side, y, w, (light.r + light.g + light.b) / most);
  };
  const auto context = [&](uint64_t item) {
    return ShadingContext{rays.bvh, rays.counts, rays.offset, 1, 0.0f, sequence_scramble(progression, item, rng),
                          sample};
  };
  // As many directions as the sample's list holds, drawn from the same table but for this point alone: shared by
  // every point, the sample's own make the whole image brighter or darker at once (Sponza under an HDRI, 4
  // samples: the Direct pass's mean 0.71-1.10 of Cycles over seeds).
  const ShadingContext table = context(kWorldDirections);
  for (int k = 0; k < drawn; ++k) {
    const std::optional<SceneLights::WorldDirection> w = world->lights.draw_world(table.point2(k, drawn));
    if (!w) break;
    const float cos_n = glm::dot(n, w->direction);
    if (!(cos_n > 0.0f) || !table.visible_direction(y, n, w->direction)) continue;
    const glm::vec3 t = terms(w->direction, w->pdf);
    add(w->direction, w->radiance, cos_n, t, t.x);
  }
  const ShadingContext own = context(kCosineDirections);
  for (int k = 0; k < cosine; ++k) {
    const glm::vec2 u = own.point2(k, cosine);
    const glm::vec3 w = cosine_direction(n, u.x, u.y);
    const float cos_n = glm::dot(n, w);
    if (!(cos_n > 0.0f)) continue;
    const SceneLights::WorldDensity density = world->lights.world_density(w);
    if (!(density.radiance.r + density.radiance.g + density.radiance.b > 0.0f)) continue;
    if (!own.visible_direction(y, n, w)) continue;
    const glm::vec3 t = terms(w, density.pdf);
    add(w, density.radiance, cos_n, t, t.y);
  }
  const ShadingContext guided_context = context(kGuidedDirections);
  for (int k = 0; k < guided; ++k) {
    const glm::vec3 u = guided_context.point3(k, guided);
    const std::optional<SkyGuide::Draw> w = guide->draw(side, y, u.x, {u.y, u.z});
    if (!w) break;
    const float cos_n = glm::dot(n, w->direction);
    if (!(cos_n > 0.0f)) continue;
    const SceneLights::WorldDensity density = world->lights.world_density(w->direction);
    if (!(density.radiance.r + density.radiance.g + density.radiance.b > 0.0f)) continue;
    if (!guided_context.visible_direction(y, n, w->direction)) continue;
    const glm::vec3 t = terms(w->direction, density.pdf);
    add(w->direction, density.radiance, cos_n, t, t.z);
  }
  return sum;
}

}  // namespace bounce::cpu
