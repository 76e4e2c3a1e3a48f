// Lambert's polygon formula for area lights, shared by the shaders (shaders/common/lights.glsl) and the host
// (native/src/cpu/lambert.h includes this file into C++ with GLM, for the ray-traced direct light), so both
// compute the very same unshadowed irradiance. Written in the common subset of GLSL and C++: arrays are fixed
// size, an output array is marked LAMBERT_OUT (GLSL `out`, nothing in C++, where the array is a pointer), and
// LAMBERT_INLINE is `inline` in C++.
#ifndef LAMBERT_INLINE
#define LAMBERT_INLINE
#endif
#ifndef LAMBERT_OUT
#define LAMBERT_OUT out
#endif

const int MAX_POLYGON = 40;
const int ELLIPSE_SEGMENTS = 32;
const float LAMBERT_PI = 3.14159265358979f;

// The cosine-weighted solid angle of a polygon seen from the origin, i.e. E = L * polygon_projected_solid_angle.
// Vertices are relative to the receiver and already clipped to its upper hemisphere.
LAMBERT_INLINE float polygon_projected_solid_angle(vec3 vertices[MAX_POLYGON], int count, vec3 n) {
  float sum = 0.0f;
  for (int i = 0; i < count; ++i) {
    // A vertex on the receiver has no direction, and its edges subtend nothing: float32 puts one there when an
    // emitter far larger than its distance collapses to a line through the receiver (a 1 m by 2e9 m strip).
    if (dot(vertices[i], vertices[i]) == 0.0f || dot(vertices[(i + 1) % count], vertices[(i + 1) % count]) == 0.0f)
      continue;
    vec3 a = normalize(vertices[i]);
    vec3 b = normalize(vertices[(i + 1) % count]);
    vec3 c = cross(a, b);
    float sin_theta = length(c);
    float theta = atan(sin_theta, dot(a, b));
    sum += dot(n, c) * (sin_theta > 1e-7f ? theta / sin_theta : 1.0f);
  }
  return 0.5f * abs(sum);
}

// Sutherland-Hodgman against the receiver's tangent plane: light below the horizon does not reach it.
LAMBERT_INLINE int clip_to_horizon(vec3 vertices[MAX_POLYGON], int count, vec3 n,
                                   LAMBERT_OUT vec3 clipped[MAX_POLYGON]) {
  int out_count = 0;
  for (int i = 0; i < count; ++i) {
    vec3 a = vertices[i];
    vec3 b = vertices[(i + 1) % count];
    float da = dot(n, a);
    float db = dot(n, b);
    if (da >= 0.0f && out_count < MAX_POLYGON) clipped[out_count++] = a;
    if ((da >= 0.0f) != (db >= 0.0f) && out_count < MAX_POLYGON) clipped[out_count++] = mix(a, b, da / (da - db));
  }
  return out_count;
}

// The emitter outline around centre c with half axes u, v: a rectangle, or an ellipse as a polygon scaled to
// the ellipse's area.
LAMBERT_INLINE int emitter_polygon(vec3 c, vec3 u, vec3 v, bool rectangle, LAMBERT_OUT vec3 vertices[MAX_POLYGON]) {
  if (rectangle) {
    vertices[0] = c - u - v;
    vertices[1] = c + u - v;
    vertices[2] = c + u + v;
    vertices[3] = c - u + v;
    return 4;
  }
  float step = 2.0f * LAMBERT_PI / float(ELLIPSE_SEGMENTS);
  // Inscribed N-gon area is (N/2) sin(2 pi / N) r^2; scale so it equals pi r^2.
  float scale = sqrt(LAMBERT_PI / (0.5f * float(ELLIPSE_SEGMENTS) * sin(step)));
  for (int i = 0; i < ELLIPSE_SEGMENTS; ++i) {
    float angle = step * float(i);
    vertices[i] = c + scale * (cos(angle) * u + sin(angle) * v);
  }
  return ELLIPSE_SEGMENTS;
}

LAMBERT_INLINE float planar_polygon_area(vec3 vertices[MAX_POLYGON], int count) {
  vec3 sum = vec3(0.0f);
  for (int i = 0; i < count; ++i) sum += cross(vertices[i], vertices[(i + 1) % count]);
  return 0.5f * length(sum);
}
