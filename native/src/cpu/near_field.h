// What a distance clamp takes from a VPL method's first bounce, given back by a ray (bias compensation, Kollig
// and Keller, "Illumination in the Presence of Weak Singularities", 2006). A VPL at distance d < c lights x as if
// it stood at c, so the VPLs miss E(x) - E_c(x) = the integral over directions of L(w) cos (1 - d^2 / c^2): one
// cosine-drawn ray from x up to c, and where it meets a surface y, pi times y's reflected direct light times
// (1 - d^2 / c^2). Light next to a lit surface (a column's foot, a corner by a sunlit floor) came out dark without
// it: the Topology method's first bounce in Sponza with shadow rays was 0.943 of Cycles (0.884 in the right
// third), 1.013 with it. The second bounce's share (y's own first-bounce light) is given back by the renderer
// that has gathered that light where the camera sees y (NearField::reflectance times it, at first_bounce_pixel),
// and estimates it from its VPLs where no pixel does (UnseenFirstBounce).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cpu/cpu_scene.h"
#include "cpu/direct_light.h"
#include "cpu/random.h"
#include "cpu/vpls.h"

namespace bounce::cpu {

// One ray's estimate of what the clamp c (metres) takes at x.
struct NearField {
  glm::vec3 irradiance{0.0f};   // of the first bounce: from y's reflected direct light of `lights`
  glm::vec3 reflectance{0.0f};  // y's albedo times (1 - d^2 / c^2): times the irradiance y receives, what it adds
  glm::vec3 position{0.0f}, normal{0.0f};  // y's; normal 0 where the ray met nothing
};

// `lights`: a sample's list; `world` as in direct_irradiance; the ray's direction from x's `progression`.
NearField near_field(const CpuScene& scene, const Surface& x, std::span<const BounceLight> lights,
                     const ShadowRays& rays, const WorldStrategies& world, float clamp, const Progression& progression,
                     Rng& rng);

// A pixel's surface, as the camera sees it.
struct SeenSurface {
  glm::vec3 position, normal;
};

// The pixel whose first-bounce irradiance y (met by the near-field ray of pixel `own`) receives: the pixel that
// sees y (y within the clamp of its surface, facing the same way); where the camera does not see y, `own` where
// it faces as y does, else none (in a corner the other face's light is another: taking the wall's for the floor
// beside it gave a corner's second bounce 1.10 of what a tight clamp gives). `point`: where y falls in the
// width x height image (image_point, in pixels); `seen(j)`: pixel j's optional SeenSurface.
template <class Seen>
std::optional<std::size_t> first_bounce_pixel(const NearField& y, std::size_t own, std::optional<glm::dvec2> point,
                                              int width, int height, float clamp, const Seen& seen) {
  constexpr float kSameFacing = 0.7f;
  if (point && point->x >= 0.0 && point->y >= 0.0 && point->x < width && point->y < height) {
    const std::size_t j = std::size_t(point->y) * std::size_t(width) + std::size_t(point->x);
    const std::optional<SeenSurface> surface = seen(j);
    if (surface && glm::distance(surface->position, y.position) < clamp &&
        glm::dot(surface->normal, y.normal) > kSameFacing)
      return j;
  }
  const std::optional<SeenSurface> surface = seen(own);
  if (surface && glm::dot(surface->normal, y.normal) > kSameFacing) return own;
  return std::nullopt;
}

// The first-bounce irradiance at y where no pixel sees y (the far side of a box on the ground, the ground under its
// edge): a few of the sample's first-bounce VPLs, drawn by the light they give y unshadowed, with shadow rays,
// estimate their light there without bias, and a near-field ray of y's own what its clamp takes. With none, the
// open ground's second bounce was 0.82 of Cycles' in the Topology method; drawn evenly, a VPL within the clamp of y
// took the Cornell box's Indirect relMSE from 5.9e-5 to 1.8e-4.
class UnseenFirstBounce {
 public:
  // `vpls`: the sample's (those of bounce 1 light y); `clamp`: their distance clamp (vpl_irradiance), and y's near
  // field's.
  UnseenFirstBounce(std::span<const Vpl> vpls, float clamp);
  // `progression` and `rng`: the near-field ray's, and the draws'.
  glm::vec3 at(const CpuScene& scene, const NearField& y, std::span<const BounceLight> lights, const ShadowRays& rays,
               const WorldStrategies& world, const Progression& progression, Rng& rng) const;

 private:
  // The first-bounce VPLs that carry light, their positions, normals and power summed over the channels in arrays
  // of their own: every point weighs them all (Sponza at 1280x720: 55,000 points a sample, 1,750 candidates).
  std::vector<float> x_, y_, z_, nx_, ny_, nz_, power_;
  std::vector<float> cap_;         // of the geometry term: pi / area, or infinity
  std::vector<glm::vec3> colour_;  // power / its sum
  float clamp_;
};

}  // namespace bounce::cpu
