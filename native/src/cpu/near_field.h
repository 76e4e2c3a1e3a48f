// What a distance clamp takes from a VPL method's first bounce, given back by a ray (bias compensation, Kollig
// and Keller, "Illumination in the Presence of Weak Singularities", 2006). A VPL at distance d < c lights x as if
// it stood at c, so the VPLs miss E(x) - E_c(x) = the integral over directions of L(w) cos (1 - d^2 / c^2): one
// cosine-drawn ray from x up to c, and where it meets a surface y, pi times y's reflected direct light times
// (1 - d^2 / c^2). Light next to a lit surface (a column's foot, a corner by a sunlit floor) came out dark without
// it: the Topology method's first bounce in Sponza with shadow rays was 0.943 of Cycles (0.884 in the right
// third), 1.013 with it. The second bounce's share of that light (y's own indirect light) is not given back.
#pragma once

#include <span>

#include <glm/vec3.hpp>

#include "cpu/cpu_scene.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"

namespace bounce::cpu {

// One ray's estimate of the irradiance the clamp c (metres) takes at x from `lights` (a sample's list; `world`
// as in direct_irradiance).
glm::vec3 near_field_irradiance(const CpuScene& scene, const Surface& x, std::span<const BounceLight> lights,
                                const ShadowRays& rays, const WorldStrategies& world, float clamp, Rng& rng);

}  // namespace bounce::cpu
