// The segment test of emitter_occluders.glsl, shared with the CPU's Topology method (native/src/scene_lights.h,
// emitter_between), which includes this file into C++ with GLM. Written in the common subset of GLSL and C++;
// EMITTERS_INLINE is `inline` in C++.
#ifndef EMITTERS_INLINE
#define EMITTERS_INLINE
#endif

// Whether triangle (a, b, c) crosses the segment y + t d at some t in (t_min, t_max) (Moller-Trumbore).
EMITTERS_INLINE bool triangle_crosses_segment(vec3 a, vec3 b, vec3 c, vec3 y, vec3 d, float t_min, float t_max) {
  vec3 e1 = b - a, e2 = c - a;
  vec3 p = cross(d, e2);
  float det = dot(e1, p);
  if (det == 0.0f) return false;
  vec3 s = (y - a) / det;
  float u = dot(s, p);
  if (u < 0.0f || u > 1.0f) return false;
  vec3 q = cross(s, e1);
  float v = dot(d, q);
  if (v < 0.0f || u + v > 1.0f) return false;
  float t = dot(e2, q);
  return t > t_min && t < t_max;
}
