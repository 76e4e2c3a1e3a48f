// CPU reference of what the Forward Light Cuts estimator converges to (Laurent et al. 2016, Sec. 5): the
// first diffuse bounce of many virtual point lights, unshadowed between light and receiver (FLC ignores
// indirect visibility), with the direct irradiance at each light shadowed. Tests compare the GPU renderer
// against it; it is never linked into libbounce.so.
//
// Light units are the engine's (bounce.h, BounceLight); the unshadowed irradiance of each light type is the one
// of shaders/common/lights.glsl, times visibility by shadow rays.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "bounce/bounce.h"
#include "embree/embree_device.h"

namespace bounce::reference {

// World-space triangle, two-sided, Lambertian with this albedo.
struct Triangle {
  std::array<glm::vec3, 3> p{};
  glm::vec3 albedo{0.8f};
};

class Scene {
 public:
  // Lights are sanitised as bounce_lights_set does: non-finite, non-positive or zero-size ones are dropped,
  // frames made orthonormal, ranges clamped.
  Scene(std::vector<Triangle> triangles, std::vector<BounceLight> lights);

  const std::vector<Triangle>& triangles() const { return triangles_; }
  const std::vector<BounceLight>& lights() const { return lights_; }
  const embree::Scene& bvh() const { return bvh_; }
  glm::vec3 bounds_min() const { return bvh_.bounds_min(); }
  glm::vec3 bounds_max() const { return bvh_.bounds_max(); }
  float diagonal() const;  // of the triangles' bounding box; 0 when empty

 private:
  std::vector<Triangle> triangles_;
  std::vector<BounceLight> lights_;
  embree::Scene bvh_;
};

struct Options {
  float epsilon = 0.01f;    // metres: d = max(epsilon, |x - y|) in Eq. 5
  float shadow_offset = 0;  // metres: shadow rays start this far off the surface; <= 0: 1e-4 of the diagonal
  int light_samples = 64;   // shadow rays per light and point: a k^2 grid (area, sun) or k^3 grid (soft point,
                            // spot ball) with k the smallest that gives at least this many; hard lights use 1
  float points_per_unit_area = 100.0f;  // continuous(): sample density over the surfaces
  int min_points_per_triangle = 1;      // continuous(): even the smallest triangle is sampled this often
  uint64_t seed = 0;                    // every random choice derives from it: same seed, same result
  bool cosine_lobe = false;             // Eq. 6's radiance (FLC's Cosine-Lobe Lights) instead of Lambertian
  int threads = 0;                      // 0: std::thread::hardware_concurrency()
};

// Shadowed direct irradiance (W/m^2, per channel) at y on the side of unit normal n, summed over the lights.
glm::vec3 irradiance(const Scene& scene, glm::vec3 y, glm::vec3 n, const Options& options);

// A virtual point light: a point of a triangle standing for `area` of its surface, with the shadowed direct
// irradiance on either side of its plane (front = the triangle's counter-clockwise normal).
struct Vpl {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};  // unit, counter-clockwise
  glm::vec3 albedo{0.0f};
  float area = 0.0f;
  glm::vec3 irradiance_front{0.0f};
  glm::vec3 irradiance_back{0.0f};
};

struct Receiver {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // unit, on the side that receives
  glm::vec3 albedo{0.8f};
};

enum class Mode {
  many_lights,  // L^ML, Eq. 4: one light at each triangle's centroid, weighted by the triangle's area
  continuous,   // the limit of jittered lights (Sec. 6, progressive rendering): the integral over all surfaces
};

// The lights of a mode. Continuous: each triangle is cut into m^2 congruent sub-triangles with m^2 >=
// max(min_points_per_triangle, area * points_per_unit_area), and one point is drawn uniformly in each
// (stratified), weighted area / m^2. Degenerate triangles and those of zero albedo make no light.
std::vector<Vpl> make_vpls(const Scene& scene, Mode mode, const Options& options);

// Radiance leaving the light toward x (two-sided: the side facing x, with that side's irradiance): Lambertian,
// albedo E / pi, or with `cosine_lobe` Eq. 6's albedo E 3 / (2 pi) cos.
glm::vec3 vpl_radiance(const Vpl& vpl, glm::vec3 x, bool cosine_lobe);
// Eq. 5: H(t_i, x, n_x), the receiver's outgoing radiance per unit area of the light (albedo included).
glm::vec3 transfer(const Vpl& vpl, const Receiver& receiver, const Options& options);
// Eq. 4: sum of transfer * area over the lights: the receiver's outgoing indirect radiance.
glm::vec3 gather(std::span<const Vpl> vpls, const Receiver& receiver, const Options& options);

// Outgoing indirect radiance at each receiver (parallel over receivers).
std::vector<glm::vec3> indirect(const Scene& scene, std::span<const Receiver> receivers, Mode mode,
                                const Options& options);
std::vector<glm::vec3> many_lights(const Scene& scene, std::span<const Receiver> receivers, const Options& options);
std::vector<glm::vec3> continuous(const Scene& scene, std::span<const Receiver> receivers, const Options& options);

// What the camera sees: width * height pixels, rows bottom to top, rays through pixel centres (crop ignored).
// The receiver is the first hit, its normal the geometric one turned toward the camera; pixels that hit
// nothing are 0 and not covered.
struct Image {
  int width = 0, height = 0;
  std::vector<glm::vec3> incident;  // outgoing indirect radiance of a white (albedo 1) receiver
  std::vector<glm::vec3> albedo;    // of the triangle each pixel sees
  std::vector<uint8_t> covered;     // 1 where the pixel's ray hits a triangle
  glm::vec3 radiance(std::size_t pixel) const { return incident[pixel] * albedo[pixel]; }
};
Image render(const Scene& scene, const BounceCamera& camera, Mode mode, const Options& options);

}  // namespace bounce::reference
