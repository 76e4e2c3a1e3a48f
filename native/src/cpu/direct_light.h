// Bounce's direct-lighting model on the CPU, with visibility by Embree shadow rays: the unshadowed irradiance of
// each light type is shaders/common/lights.glsl's (units in bounce.h, BounceLight), times the visible fraction
// of the light. The topology method lights its view samples and its VPLs with it; the CPU references use it
// with many shadow rays.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "bounce/bounce.h"
#include "cpu/random.h"
#include "embree/embree_device.h"

namespace bounce::cpu {

struct ShadowRays {
  const embree::Scene& bvh;
  float offset;  // rays start this far off the surface, along its normal
  int samples;   // per light and point: a k^2 grid (area, sun) or k^3 grid (soft point, spot ball) with k the
                 // smallest giving at least this many, jittered; hard lights use 1
  embree::Scene::HitFilter counts = {};  // which hits block (CpuScene::opaque: not where cut-outs have holes)
  float softness = 1.0f;  // the shadows' light size over the light's own (settings.shadow_softness; 0: hard)
};

// lights.glsl's spot_attenuation: the cone and its smooth edge, toward unit direction `from_light`.
float spot_attenuation(const BounceLight& light, glm::vec3 from_light);

// Shadowed direct irradiance (W/m^2, per channel) at y on the side of unit normal n from one light.
glm::vec3 light_irradiance(const BounceLight& light, glm::vec3 y, glm::vec3 n, const ShadowRays& rays, Rng& rng);
// Summed over the lights.
glm::vec3 direct_irradiance(std::span<const BounceLight> lights, glm::vec3 y, glm::vec3 n, const ShadowRays& rays,
                            Rng& rng);

}  // namespace bounce::cpu
