#include "cpu/near_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "radiometry.h"
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

UnseenFirstBounce::UnseenFirstBounce(std::span<const Vpl> vpls, float clamp) : clamp_(clamp) {
  for (const Vpl& vpl : vpls) {
    const float power = vpl.power.r + vpl.power.g + vpl.power.b;
    if (vpl.bounce != 1 || !(power > 0.0f) || !std::isfinite(power)) continue;
    x_.push_back(vpl.position.x);
    y_.push_back(vpl.position.y);
    z_.push_back(vpl.position.z);
    nx_.push_back(vpl.normal.x);
    ny_.push_back(vpl.normal.y);
    nz_.push_back(vpl.normal.z);
    power_.push_back(power);
    cap_.push_back(vpl.area > 0.0f ? kPi / vpl.area : std::numeric_limits<float>::infinity());
    colour_.push_back(vpl.power / power);
  }
}

glm::vec3 UnseenFirstBounce::at(const CpuScene& scene, const NearField& y, std::span<const BounceLight> lights,
                                const ShadowRays& rays, const WorldStrategies& world, const Progression& progression,
                                Rng& rng) const {
  constexpr int kDraws = 16;
  const Surface y_surface{y.position, y.normal, y.normal, glm::vec3(0.0f), glm::vec3(0.0f)};
  const glm::vec3 own_near = near_field(scene, y_surface, lights, rays, world, clamp_, progression, rng).irradiance;
  const std::size_t count = power_.size();
  // The irradiance (summed over the channels) each VPL gives y unshadowed, clamped as cpu::vpl_irradiance and
  // capped as the shading pass's vpl_irradiance (ssvp_common.glsl), in a loop the compiler vectorizes
  // (CMakeLists.txt).
  thread_local std::vector<float> light;
  light.resize(count);
  const float clamp2 = clamp_ * clamp_;
  const glm::vec3 p = y.position, n = y.normal;
  for (std::size_t l = 0; l < count; ++l) {
    const float dx = x_[l] - p.x, dy = y_[l] - p.y, dz = z_[l] - p.z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    const float along_vpl = std::max(-(nx_[l] * dx + ny_[l] * dy + nz_[l] * dz), 0.0f);
    const float along_y = std::max(n.x * dx + n.y * dy + n.z * dz, 0.0f);
    const float geometry = along_vpl * along_y / std::max(d2 * std::max(d2, clamp2), 1e-30f);
    light[l] = power_[l] * std::min(geometry, cap_[l]) * (1.0f / kPi);
  }
  double total = 0.0;
  for (std::size_t l = 0; l < count; ++l) total += double(light[l]);
  if (!(total > 0.0) || !std::isfinite(total)) return own_near;
  const float offset = scene.ray_offset();
  const double start = double(rng.next());
  glm::vec3 sum(0.0f);
  double cumulative = 0.0;
  std::size_t l = 0;
  for (int k = 0; k < kDraws; ++k) {
    const double target = (double(k) + start) / kDraws * total;
    for (; l + 1 < count; ++l) {
      const double next = cumulative + double(light[l]);
      if (next > target) break;
      cumulative = next;
    }
    if (!(light[l] > 0.0f)) continue;
    const glm::vec3 origin(x_[l] + nx_[l] * offset, y_[l] + ny_[l] * offset, z_[l] + nz_[l] * offset);
    if (scene.clear_between(origin, y.position + y.normal * offset)) sum += colour_[l] * float(total);
  }
  return sum / float(kDraws) + own_near;
}

}  // namespace bounce::cpu
