// Bounce's direct-lighting model on the CPU, with visibility by Embree shadow rays: the unshadowed irradiance of
// each light type is shaders/common/lights.glsl's (units in bounce.h, BounceLight), times the visible fraction
// of the light. The topology method lights its view samples and its VPLs with it; the CPU references use it
// with many shadow rays.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "bounce/bounce.h"
#include "cpu/random.h"
#include "cpu/sky_guide.h"
#include "embree/embree_device.h"
#include "scene_lights.h"

namespace bounce::cpu {

struct ShadowRays {
  const embree::Scene& bvh;
  float offset;  // rays start this far off the surface, along its normal
  int samples;   // per light and point: k^2 (area, sun) or k^3 (soft point, spot ball) points of the light's
                 // Sobol sequence, with k the smallest giving at least this many; hard lights use 1
  embree::Scene::HitFilter counts = {};  // which hits block (CpuScene::opaque: not where cut-outs have holes)
  float softness = 1.0f;  // the shadows' light size over the light's own (settings.shadow_softness; 0: hard)
};

// A pixel's place in its render's samples: the shadow rays of its sample `sample` take the next points of Sobol's
// sequence (sampling.h), scrambled per light by seeds drawn from `key` (the pixel's, the same for all its samples),
// so that over the samples they cover each light, and the sky, evenly instead of at random: the points of any
// 2^m samples in a row are stratified, and each point is uniform. Without one, a query's points are scrambled at
// random (`rng`) and start from the first.
struct Progression {
  uint64_t key;
  uint32_t sample;

  // The scramble of `item`'s sequence (a light, or another integral of the pixel's).
  glm::uvec3 scramble(uint64_t item) const {
    Rng drawn(key, 0x5343524dull, item);
    return {drawn.next_bits(), drawn.next_bits(), drawn.next_bits()};
  }
};

// lights.glsl's spot_attenuation: the cone and its smooth edge, toward unit direction `from_light`.
float spot_attenuation(const BounceLight& light, glm::vec3 from_light);

// Shadowed direct irradiance (W/m^2, per channel) at y on the side of unit normal n from one light.
glm::vec3 light_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, const ShadowRays& rays, Rng& rng);
// The world's light at a point by two strategies of multiple importance sampling: as many directions as the
// sample's list of lights holds for the world, drawn for the point alone from the world's table (draw_world: in
// proportion to radiance x solid angle), against `cosine` directions drawn in proportion to cos / pi (Veach's power
// heuristic: each direction's light is weighted by its strategy's (K p)^2 over (K p(w))^2 + (K_c cos / pi)^2, so
// the sum stays unbiased, and the strategy far likelier to draw a direction carries nearly all of its light).
// The table's directions go where the environment is bright, which a point in an atrium seldom sees; its
// cosine-weighted directions find the sky through the opening.
// A third strategy, where a SkyGuide has learned where a point's region sees the world: as many directions again as
// the cosine-weighted ones, drawn from the guide, weighed the same way; every direction that finds light teaches
// the guide.
struct WorldStrategies {
  const SceneLights& lights;  // whose sample() made the list of lights: its world's table and directions' count
  int cosine;                 // cosine-weighted directions per point
  SkyGuide* guide = nullptr;  // learned over the render's samples; none: two strategies
};

// Summed over the lights; with `world` (whose `lights` made this list), the world's light by both strategies
// instead of the list's world directions.
glm::vec3 direct_irradiance(std::span<const BounceLight> lights, glm::vec3 y, glm::vec3 n, const ShadowRays& rays,
                            Rng& rng, const WorldStrategies* world = nullptr, const Progression* progression = nullptr);

}  // namespace bounce::cpu
