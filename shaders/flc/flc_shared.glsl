// Forward Light Cuts math shared by the shaders and the host: native/src/passes/flc/flc_math.h includes this
// file into C++ (with GLM), so the unit tests check the very functions the GPU runs, and a compute shader test
// checks that both agree. Written in the common subset of GLSL and C++: no out parameters, no overloads, no
// GLSL-only built-ins; pcg_hash is shaders/common/random.glsl on the GPU and native/src/sampling.h on the host.
// FLC_INLINE is `inline` in C++ (the functions live in a header) and nothing in GLSL.
#ifndef FLC_INLINE
#define FLC_INLINE
#endif

// Indirect Shadows' ray maps (FlcPass::trace_ray_maps): bins per side of the octahedral map of directions around a
// light the topology's grid cannot place. 256 bins over the sphere, about 13 degrees each.
#define FLC_RAY_MAP_BINS_PER_SIDE 16
#define FLC_RAY_MAP_BINS (FLC_RAY_MAP_BINS_PER_SIDE * FLC_RAY_MAP_BINS_PER_SIDE)

// Whether a receiver at `distance` from a light with a ray map is reached by it when the ray of the receiver's bin
// met a surface at `hit` before any empty voxel: a receiver where that ray ends lies about as far, and within a bin
// of 13 degrees the distance to one plane varies by a fifth at 60 degrees of incidence.
FLC_INLINE bool flc_ray_map_reaches(float hit, float distance) { return hit >= 0.75f * distance; }

// S_k = S_0 mu^k (Eq. 17).
FLC_INLINE float flc_level_area(float s0, float mu, int k) {
  float s = s0;
  for (int j = 0; j < k; ++j) s *= mu;
  return s;
}

// 1 / S-bar_k = sum_{j <= k} 1 / S_j (Sec. 4). A triangle of area A gets a level <= k with probability
// A / S-bar_k: Eq. 3 as printed gives this cumulative probability as P(t_i in L^k). The probability of level k
// itself is A / S-bar_k - A / S-bar_{k-1} = A / S_k, and that is what the unbiasedness condition (Eq. 9) needs
// with F^k = S_k f^k (Eq. 10): sum_k S_k f^k A / S_k = A sum_k f^k = A.
FLC_INLINE float flc_inverse_cumulative_area(float s0, float mu, int k) {
  float sum = 0.0f;
  float s = s0;
  for (int j = 0; j <= k; ++j) {
    sum += 1.0f / s;
    s *= mu;
  }
  return sum;
}

// Alg. 1 (ComputeLevel): the level of a triangle of area `area` <= S-bar_N drawn by its uniform random u in
// [0, 1), or -1 when it is discarded.
FLC_INLINE int flc_level(float u, float area, float s0, float mu, int levels) {
  float inverse_cumulative = 0.0f;
  float s = s0;
  for (int k = 0; k <= levels; ++k) {
    inverse_cumulative += 1.0f / s;
    if (u < area * inverse_cumulative) return k;
    s *= mu;
  }
  return -1;
}

// A triangle larger than S-bar_N even after the divergent pipeline's maximum subdivision would be kept with
// a probability above 1. It is kept always and chooses its level as a triangle of area S-bar_N would, with
// its light scaled by this weight A / S-bar_N: the expectation of Eq. 8 is again A (no energy is lost).
FLC_INLINE float flc_oversize_weight(float area, float inverse_cumulative_n) { return max(1.0f, area * inverse_cumulative_n); }

// D_k, the distance level k reaches (Fig. 6): D_near mu^(k/2). Eq. 18 prints D_k = sqrt(S_0 mu^k) = sqrt(S_k),
// which with Eq. 1 puts D_0 at D_near sqrt(4 pi / N_avg), and then about pi lights of each level reach a
// pixel whatever N_avg is. Scaling Eq. 18 by sqrt(N_avg / (4 pi)) keeps its geometric progression and meets
// Eq. 1's own heuristic: D_0 = D_near, and about N_avg lights of level k lie within D_k of a receiver
// surrounded by surfaces (4 pi D_k^2 / S_k = N_avg), so N_avg sets both quality and cost (Fig. 10). Any
// increasing D_k keeps the estimator unbiased (Eq. 11 holds for every choice).
FLC_INLINE float flc_level_distance(float d0, float mu, int k) { return d0 * sqrt(flc_level_area(1.0f, mu, k)); }

// f~^k(d), the piecewise-affine partition of unity of Eq. 16, at d = d(t_i, x) of Eq. 14, for level k whose
// neighbours sit at D_{k-1} (lower), D_k (centre) and D_{k+1} (upper); the splatting shader passes the three
// distances in, computed once per VPL. Two departures
// from the printed text, both needed for sum_k f~^k(d) = 1 at every d > 0 (Eq. 11):
// - level 0 is 1 on ]0, D_0] and falls on ]D_0, D_1] like every other level (as printed it is 1 up to D_1,
//   which overlaps level 1's rise on ]D_0, D_1]);
// - the last level stays 1 beyond D_N instead of Eq. 18's D_{N+1} = D_N, which would drop all light from
//   beyond D_N. Its lights are the fewest (expected count A_scene / S_N) and splat over the whole view.
FLC_INLINE float flc_partition_between(float d, float lower, float centre, float upper, bool first, bool last) {
  if (d <= centre) {
    if (first) return 1.0f;
    return d > lower ? (d - lower) / (centre - lower) : 0.0f;
  }
  if (last) return 1.0f;
  return d < upper ? (upper - d) / (upper - centre) : 0.0f;
}

FLC_INLINE float flc_partition(float d, int k, int levels, float d0, float mu) {
  return flc_partition_between(d, k > 0 ? flc_level_distance(d0, mu, k - 1) : 0.0f, flc_level_distance(d0, mu, k),
                               k < levels ? flc_level_distance(d0, mu, k + 1) : 0.0f, k == 0, k == levels);
}

// The largest d at which level k's partition function is non-zero; negative for "unbounded" (the last level).
FLC_INLINE float flc_support_distance(int k, int levels, float d0, float mu) {
  return k < levels ? flc_level_distance(d0, mu, k + 1) : -1.0f;
}

// Alg. 2 (RegularRand), with a PCG hash after the xor: the xor of the three vertex randoms (and, here, the
// instance's, so instances of one mesh are decimated independently) with the per-sample u_rand is uniform,
// and the hash decorrelates triangles whose xors differ in a few bits only.
FLC_INLINE uint flc_triangle_random(uint u_rand, uint v0, uint v1, uint v2, uint instance) {
  return pcg_hash(u_rand ^ v0 ^ v1 ^ v2 ^ instance);
}

FLC_INLINE float flc_unit(uint h) { return float(h >> 8) * (1.0f / 16777216.0f); }

// A uniform point of a triangle as barycentric weights of (p0, p1, p2), from two uniform numbers.
FLC_INLINE vec3 flc_triangle_point(float u1, float u2) {
  float r = sqrt(u1);
  return vec3(1.0f - r, r * (1.0f - u2), r * u2);
}
