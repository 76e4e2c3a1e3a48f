#include "cpu/view_probes.h"

#include <cmath>
#include <optional>

#include <glm/matrix.hpp>

#include "cpu/camera_ray.h"
#include "sampling.h"

namespace bounce::cpu {

std::vector<ViewProbe> camera_probes(const glm::mat4& view_projection, const CpuScene& scene, uint32_t seed,
                                     int per_axis) {
  std::vector<ViewProbe> probes;
  const glm::dmat4 clip_to_world = glm::inverse(glm::dmat4(view_projection));
  for (int cell = 0; cell < per_axis * per_axis; ++cell) {
    const uint32_t key = hash_combine(seed, static_cast<uint32_t>(cell));
    const double x = (cell % per_axis + hash_to_unit(key)) / per_axis,
                 y = (cell / per_axis + hash_to_unit(key ^ 0x9e37u)) / per_axis;
    const CameraRay ray = camera_ray(clip_to_world, 2.0 * x - 1.0, 2.0 * y - 1.0);
    if (!std::isfinite(ray.direction.x) || !std::isfinite(ray.origin.x)) continue;
    const std::optional<embree::Hit> hit = scene.intersect(ray.origin, ray.direction, 0.0f, ray.tmax);
    if (!hit) continue;
    const Surface surface = scene.surface(*hit, ray.direction);
    probes.push_back({surface.position, surface.shading_normal, surface.albedo});
  }
  return probes;
}

}  // namespace bounce::cpu
