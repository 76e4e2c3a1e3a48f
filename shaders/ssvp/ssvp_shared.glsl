// Screen-Space VPL Propagation math shared by the shaders and the host: native/src/passes/ssvp/ssvp_math.h
// includes this file into C++ (with GLM), so the unit tests check the very functions the GPU runs. Written in
// the common subset of GLSL and C++ (see shaders/flc/flc_shared.glsl). SSVP_INLINE is `inline` in C++.
#ifndef SSVP_INLINE
#define SSVP_INLINE
#endif

// Van der Corput radical inverse in base 2, gamma(k) of Eq. 1: the bits of k mirrored about the binary point.
SSVP_INLINE float ssvp_van_der_corput(uint k) {
  uint bits = k;
  bits = (bits << 16u) | (bits >> 16u);
  bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
  bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
  bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
  bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
  return float(bits >> 8u) * (1.0f / 16777216.0f);
}

// Eq. 1: the k-th of n points of the 2-D Hammersley set, (k / n, gamma(k)).
SSVP_INLINE vec2 ssvp_hammersley(uint k, uint n) { return vec2(float(k) / float(n), ssvp_van_der_corput(k)); }

// Heidrich-Seidel paraboloid map (the paper's Eq. 3, f = 1/2 - (x^2 + y^2) / 2): a unit direction d of the
// upper hemisphere (d.z >= 0, z along the cluster normal) maps to the unit-disk point d.xy / (1 + d.z).
SSVP_INLINE vec2 ssvp_paraboloid_point(vec3 d) { return vec2(d.x, d.y) / (1.0f + d.z); }

// The inverse: the direction of the disk point p (|p| <= 1).
SSVP_INLINE vec3 ssvp_paraboloid_direction(vec2 p) {
  float r2 = p.x * p.x + p.y * p.y;
  return vec3(2.0f * p.x, 2.0f * p.y, 1.0f - r2) / (1.0f + r2);
}

// Jacobian of the map: the solid angle per unit of disk area at p, 4 / (1 + |p|^2)^2. It integrates to 2 pi
// over the unit disk (the hemisphere) and halves from the centre (the normal) to the rim (the horizon).
SSVP_INLINE float ssvp_paraboloid_solid_angle_density(vec2 p) {
  float q = 1.0f + p.x * p.x + p.y * p.y;
  return 4.0f / (q * q);
}

// Eq. 2 as intended (Dong et al. 2009): a position term over a length scale (the scene's size, so the metric is
// scale-free) and a penalty for dissimilar normals. As printed, Eq. 2 adds (n_i . n_j)^+, which would push apart
// VPLs with similar normals. Both terms lie in [0, 1] for points of the scene: distance / diameter and
// (1 - n_i . n_j) / 2.
SSVP_INLINE float ssvp_cluster_distance(vec3 p, vec3 n, vec3 centre, vec3 centre_normal, float w1, float w2,
                                        float length_scale) {
  vec3 d = p - centre;
  return w1 * sqrt(d.x * d.x + d.y * d.y + d.z * d.z) / length_scale +
         w2 * 0.5f * (1.0f - (n.x * centre_normal.x + n.y * centre_normal.y + n.z * centre_normal.z));
}
