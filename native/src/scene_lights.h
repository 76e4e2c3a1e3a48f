// The lights of one sample. Every pass lights the scene with a list of lights; besides the caller's lamps, that
// list holds, per sample, the other things a Blender scene lights with, turned into lights the passes already
// shade, shadow and bounce:
//  - the world (uniform colour or equirectangular environment): `world_lights` directions, drawn in proportion to
//    radiance x solid angle from a table of the environment, so each carries the same power, and spread over the
//    samples by one low-discrepancy sequence (the i-th direction of the render is its i-th R2 point). Each is a sun
//    of irradiance L(w) / (K p(w)): their average over the samples converges to the sky's visibility integral
//    (the sum over directions of L V cos / p). The ray-traced paths draw directions of their own per point
//    instead, from the same table (draw_world) and cosine-weighted, weighed by world_density()
//    (cpu/direct_light.h, WorldStrategies).
//  - emissive surfaces: each triangle with emission is a two-sided triangle light of its radiance, shaded by
//    Lambert's formula (exact unshadowed irradiance); when there are more than `emission_lights`, that many are
//    drawn each sample in proportion to their power (systematic sampling), each of radiance L / (K p).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "bounce/bounce.h"
#include "gpu_scene.h"

namespace bounce {

// Blender's equirectangular mapping of a unit direction e (z up) to uv in [0,1]^2, and its inverse: Cycles'
// direction_to_equirectangular, u = 0.5 - atan2(e.y, e.x) / 2 pi (+x at the image's centre, +y at a quarter).
glm::vec2 equirect_uv(glm::vec3 e);
glm::vec3 equirect_direction(glm::vec2 uv);

// The world's radiance toward a direction (BounceWorld's definition).
class WorldRadiance {
 public:
  WorldRadiance(const BounceWorld& world, const TextureData* environment);
  glm::vec3 operator()(glm::vec3 direction) const;
  const TextureData* environment() const { return environment_; }
  glm::vec3 background() const { return background_; }

 private:
  glm::vec3 background_;
  const TextureData* environment_;
  glm::mat3 world_to_environment_;
};

// An emissive triangle drawn this sample, as the scene geometry it is: VPL light sent towards it stops there
// (shaders/common/emitter_occluders.glsl). Its corners (w unused), in the GPU's std430 layout.
struct EmitterOccluder {
  glm::vec4 a, b, c;
};

// Whether one of `emitters` crosses the segment from y to x further than `margin` from both ends: the rule of
// emitter_occluders.glsl for the CPU's VPLs (the Topology method's clusters and gates).
bool emitter_between(std::span<const EmitterOccluder> emitters, glm::vec3 y, glm::vec3 x, float margin);

// A sun of `irradiance` shining from unit `direction` (toward the sky): how a direction of the world lights.
BounceLight world_sun(glm::vec3 direction, glm::vec3 irradiance);

class SceneLights {
 public:
  // The lights of sample `sample` of a render with `seed`: the caller's lamps first (same indices), then the
  // world's directions, then the emissive triangles. Tables are rebuilt only when the scene changed.
  const std::vector<BounceLight>& sample(const GpuScene& scene, const BounceSettings& settings, uint32_t sample,
                                         uint32_t seed);
  // How many lights of the list are the caller's lamps.
  std::size_t lamp_count() const { return lamp_count_; }
  // How many follow the lamps as the world's directions; the emissive triangles come after them.
  std::size_t world_count() const { return world_count_; }
  // The emissive triangles among this sample's lights, as occluders.
  const std::vector<EmitterOccluder>& emitter_occluders() const { return occluders_; }
  // The density (per steradian) with which each of this sample's world directions was drawn, in their order.
  const std::vector<float>& world_pdfs() const { return world_pdfs_; }
  // The density with which the world's directions are drawn toward unit world direction `w`, and the radiance they
  // carry from there (the table's), for multiple importance sampling against other strategies.
  struct WorldDensity {
    float pdf;
    glm::vec3 radiance;
  };
  WorldDensity world_density(glm::vec3 w) const;
  // The world direction that u in [0,1)^2 draws from the table (as the sample's world directions are drawn), the
  // radiance it carries and its density per steradian; none without a world that lights.
  struct WorldDirection {
    glm::vec3 direction, radiance;
    float pdf;
  };
  std::optional<WorldDirection> draw_world(glm::vec2 u) const;
  // The largest radiance of the world's table (its channels summed).
  float world_peak() const { return world_peak_; }

 private:
  struct Emitter {
    glm::vec3 a, b, c, radiance;
  };
  struct WorldTexel {
    glm::vec3 radiance;
    float u0, u1, z0, z1;  // the texel's span in u, and in sin(elevation)
  };
  void update(const GpuScene& scene);
  void add_world(const BounceSettings& settings, uint32_t sample, uint32_t seed);
  void add_emitters(const BounceSettings& settings, uint32_t sample, uint32_t seed);

  uint64_t geometry_version_ = 0, world_version_ = 0;
  std::vector<Emitter> emitters_;
  std::vector<double> emitter_cdf_;  // cumulative power, emitters_.size() + 1 entries
  std::vector<WorldTexel> world_texels_;
  std::vector<double> world_cdf_;  // cumulative radiance x solid angle, row after row (bottom first)
  std::size_t world_width_ = 1;
  float world_peak_ = 0.0f;
  std::vector<double> world_row_cdf_;  // the rows' marginal: world_cdf_ at each row's start, and the total
  glm::mat3 environment_to_world_{1.0f}, world_to_environment_{1.0f};
  std::vector<BounceLight> lights_;
  std::vector<float> world_pdfs_;  // of the world's directions among lights_
  std::vector<EmitterOccluder> occluders_;
  std::size_t lamp_count_ = 0, world_count_ = 0;
};

}  // namespace bounce
