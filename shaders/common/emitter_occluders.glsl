// Emissive triangles are scene geometry: light sent towards one lands on it and goes no further. VPL methods
// without exact indirect visibility (FLC; SSVP's clustered maps, too coarse for this) would send it through, and
// an emitter lights most the surfaces right next to it, which it hides most: the ceiling 1 cm above a hanging
// panel relit the whole room through the panel (Cornell box lit by its panel: FLC's first bounce 2.9x Cycles',
// SSVP's 1.5x). So a VPL does not reach a receiver across an emitter drawn this sample. Emitters not drawn this
// sample (more than Emissive Triangles of them) do not block: the leak is then reduced, not removed.
// Mirror: native/src/scene_lights.h, EmitterOccluder.

struct EmitterOccluder {
  vec4 a;  // corners; w unused
  vec4 b;
  vec4 c;
};

layout(std430, binding = 12) readonly buffer EmitterOccluders {
  uvec4 emitter_occluder_count;  // x
  EmitterOccluder emitter_occluders[];
};

// Whether an emitter crosses the segment from y to x, further than `margin` from both ends (the surfaces they lie
// on, an emitter's own included, do not count).
bool emitter_between(vec3 y, vec3 x, float margin) {
  vec3 d = x - y;
  float length_d = length(d);
  if (!(length_d > 2.0 * margin)) return false;
  float t_min = margin / length_d, t_max = 1.0 - t_min;
  for (uint i = 0u; i < emitter_occluder_count.x; ++i) {
    // Moller-Trumbore.
    vec3 a = emitter_occluders[i].a.xyz;
    vec3 e1 = emitter_occluders[i].b.xyz - a, e2 = emitter_occluders[i].c.xyz - a;
    vec3 p = cross(d, e2);
    float det = dot(e1, p);
    if (det == 0.0) continue;
    vec3 s = (y - a) / det;
    float u = dot(s, p);
    if (u < 0.0 || u > 1.0) continue;
    vec3 q = cross(s, e1);
    float v = dot(d, q);
    if (v < 0.0 || u + v > 1.0) continue;
    float t = dot(e2, q);
    if (t > t_min && t < t_max) return true;
  }
  return false;
}
