// Screen-Space VPL Propagation (Aranha et al. 2020), host side: the functions of shaders/ssvp/ssvp_shared.glsl
// compiled for the host, the sample sets the pass uploads, the choice of the main light and the k-means
// clustering of the first-bounce VPLs (Sec. II-A). All deterministic; unit-tested in tests/native.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "bounce/bounce.h"
#include "sampling.h"

namespace bounce::ssvp {

using glm::sqrt;
using glm::vec2;
using glm::vec3;
using uint = uint32_t;

#define SSVP_INLINE inline
#include "ssvp/ssvp_shared.glsl"
#undef SSVP_INLINE

// The n points of Eq. 1, shifted modulo 1 by `rotation` (Cranley-Patterson). A sample's rotation depends only on
// its index and the seed, so a still scene samples the same VPLs every frame (Sec. III-C); the samples' rotations
// follow an R2 sequence, so together they cover the RSM.
std::vector<glm::vec2> hammersley_set(uint32_t n, glm::vec2 rotation);

// `n` points uniform on the unit disk for the paraboloid maps: the Hammersley set through Shirley and Chiu's
// concentric map (area-preserving, so uniform; PBRT's disk sampling, [9] of the paper).
std::vector<glm::vec2> disk_set(uint32_t n, glm::vec2 rotation);

// The paper bounces one main light, from one reflective shadow map. Every light bounces here: each sample makes
// `count` draws, systematic over the lights' estimated flux into the scene's bounding sphere (centre, radius): draw
// j falls at (j + u) / count of the lights' cumulative flux, u in [0, 1), so a light of share p is drawn
// floor(count p) or ceil(count p) times. A light drawn m times bounces once, its intensity weighted by
// m / (count p) and with m / count of the sample's VPLs: each VPL carries about the same flux, and over samples
// each light bounces with its own weight. One draw per sample (the former rule) left a sky's first bounce to one
// of its directions: which one decided where all of it landed (Sponza under forest.exr, 16 samples: 0.86 of
// Cycles' first bounce). `flux_factors` (empty: 1 each) scale each light's estimated flux: the guide's factor of
// a world direction drawn by where its light reaches the view (SceneLights::guide_world), whose irradiance is
// divided by that factor, so that the sky's directions keep their share of the draws. In light-index order; none
// when no light emits into the scene.
struct LightDraw {
  int index = -1;
  int draws = 0;        // m
  float weight = 0.0f;  // m / (count p)
};
std::vector<LightDraw> draw_bouncing_lights(std::span<const BounceLight> lights, glm::vec3 centre, float radius,
                                            int count, float u, std::span<const float> flux_factors);
float estimated_flux_into_sphere(const BounceLight& light, glm::vec3 centre, float radius);

struct ClusterPoint {
  glm::vec3 position;
  glm::vec3 normal;  // unit
};

struct Cluster {
  glm::vec3 position;  // the members' mean
  glm::vec3 normal;    // the members' normalised normal sum
  uint32_t count = 0;
};

struct ClusterMetric {
  float w1 = 0.6f, w2 = 0.4f;  // Eq. 2 weights (the paper's values)
  float length_scale = 1.0f;   // positions are measured against this (the scene's diameter)
};

struct Clustering {
  std::vector<Cluster> clusters;     // none empty; fewer than asked when there are fewer distinct points
  std::vector<uint32_t> assignment;  // one cluster index per point
  int iterations = 0;
};

// Lloyd's k-means under the metric of Eq. 2 (ssvp_cluster_distance). `seeds` (the previous frame's clusters,
// Sec. III-C) start the iteration; missing seeds are added by k-means++ drawn from `seed`. An empty cluster is
// re-seeded with the point farthest from its centre, or dropped when every point already sits on a centre.
// A cluster whose normals cancel takes the normal of its member nearest the mean.
Clustering cluster_points(std::span<const ClusterPoint> points, int k, const ClusterMetric& metric,
                          std::span<const Cluster> seeds, uint32_t seed, int max_iterations = 16);

}  // namespace bounce::ssvp
