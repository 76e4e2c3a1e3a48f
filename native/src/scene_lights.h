// The lights of one sample. Every pass lights the scene with a list of lights; besides the caller's lamps, that
// list holds, per sample, the other things a Blender scene lights with, turned into lights the passes already
// shade, shadow and bounce:
//  - the world (uniform colour or equirectangular environment): `world_lights` directions, drawn in proportion to
//    radiance x solid angle from a table of the environment, so each carries the same power, and spread over the
//    samples by one low-discrepancy sequence (the i-th direction of the render is its i-th R2 point). Each is a sun
//    of irradiance L(w) / (K p(w)): their average over the samples converges to the sky's visibility integral
//    (the sum over directions of L V cos / p). The ray-traced paths draw directions of their own per point
//    instead, from the same table (draw_world) and cosine-weighted, weighed by world_density()
//    (cpu/direct_light.h, WorldStrategies). Guided (guide_world), the sample's directions are drawn in proportion
//    to radiance x solid angle x a factor of their bin of direction: how much of their light reaches what the
//    camera sees (cpu/world_reach.h), mixed with the table's own density.
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
#include "sampling.h"

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
  // Draws the sample's world directions from now on in proportion to the table's density times, per bin of direction
  // (sphere_bins), 1 - kGuidedShare + kGuidedShare x `reach` / its mean under the table's density; reach empty, or
  // zero wherever the world shines: from the table alone. Half the table's own density stays everywhere, so no
  // direction weighs more than twice what it would unguided where the reach learned from a few probes missed its
  // light (the sunlit room under forest.exr, SSVP, 12 seeds, first-bounce relMSE 4x4 median at 16 samples, the guide
  // renewed every sample: 5.79e-5 unguided, 4.08e-5 with a quarter kept, 3.75e-5 with half).
  static constexpr float kGuidedShare = 0.5f;
  // Whether the sample's lights will hold world directions: the setting asks for some and the world shines.
  bool world_lights(const GpuScene& scene, const BounceSettings& settings);
  void guide_world(std::span<const float> reach);
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
  // For each of this sample's world directions, in their order, the guide's factor on the table's density (1
  // unguided): the estimated share of its light that reaches the view, relative to the world's mean.
  const std::vector<float>& world_guide_factors() const { return world_guide_factors_; }
  // The density with which the world's table draws directions toward unit world direction `w`, and the radiance they
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
    float guide_factor = 1.0f;  // of the guided draws (guide_world): their density over the table's
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
  struct WorldTable {
    std::vector<double> cdf;      // cumulative radiance x solid angle (x a factor when guided), row after row
    std::vector<double> row_cdf;  // the rows' marginal: cdf at each row's start, and the total
    double total() const { return cdf.empty() ? 0.0 : cdf.back(); }
  };
  static WorldTable table_of(std::vector<double> cdf, std::size_t width);
  // The direction that u draws from `table`, whose texels' weights are the world table's times `factors` per bin
  // of direction (none: 1).
  std::optional<WorldDirection> draw_from(const WorldTable& table, std::span<const float> factors, glm::vec2 u) const;
  void update(const GpuScene& scene);
  void add_world(const BounceSettings& settings, uint32_t sample, uint32_t seed);
  void add_emitters(const BounceSettings& settings, uint32_t sample, uint32_t seed);

  uint64_t geometry_version_ = 0, world_version_ = 0;
  std::vector<Emitter> emitters_;
  std::vector<double> emitter_cdf_;  // cumulative power, emitters_.size() + 1 entries
  std::vector<WorldTexel> world_texels_;
  static_assert(sphere_bins::kCount <= 256);
  std::vector<uint8_t> world_bins_;   // per texel, the bin of direction of its centre, in world coordinates
  WorldTable world_table_;            // rows bottom first
  WorldTable guided_table_;           // empty unguided
  std::vector<float> guide_factors_;  // per bin, when guided
  std::size_t world_width_ = 1;
  float world_peak_ = 0.0f;
  glm::mat3 environment_to_world_{1.0f}, world_to_environment_{1.0f};
  std::vector<BounceLight> lights_;
  std::vector<float> world_guide_factors_;  // of the world's directions among lights_
  std::vector<EmitterOccluder> occluders_;
  std::size_t lamp_count_ = 0, world_count_ = 0;
};

}  // namespace bounce
