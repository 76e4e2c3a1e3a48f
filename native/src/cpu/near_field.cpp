#include "cpu/near_field.h"

#include <glm/geometric.hpp>

#include "sampling.h"

namespace bounce::cpu {

NearField near_field(const CpuScene& scene, const Surface& x, std::span<const BounceLight> lights,
                     const ShadowRays& rays, const WorldStrategies& world, float clamp, const Progression& progression,
                     Rng& rng) {
  const glm::vec2 u = sobol_point(progression.sample, glm::uvec2(progression.scramble(0)));
  const glm::vec3 direction = cosine_direction(x.shading_normal, u.x, u.y);
  if (!(glm::dot(direction, x.normal) > 0.0f)) return {};
  const auto hit = scene.intersect(x.position + x.normal * scene.ray_offset(), direction, 0.0f, clamp);
  if (!hit) return {};
  const Surface y = scene.surface(*hit, direction);
  const float d = hit->t / clamp;
  // pi times y's radiance, albedo / pi times its irradiance
  const glm::vec3 reflectance = y.albedo * (1.0f - d * d);
  return {reflectance * direct_irradiance(lights, y.position, y.shading_normal, rays, rng, &world), reflectance,
          y.position, y.shading_normal};
}

}  // namespace bounce::cpu
