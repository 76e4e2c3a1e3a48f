// Emissive triangles are scene geometry: light sent towards one lands on it and goes no further. VPL methods
// without exact indirect visibility (FLC; SSVP's clustered maps and the Topology method's clusters, too coarse for
// this) would send it through, and an emitter lights most the surfaces right next to it, which it hides most: the
// ceiling 1 cm above a hanging panel relit the whole room through the panel (Cornell box lit by its panel: FLC's
// first bounce 2.9x Cycles', SSVP's 1.5x, the Topology method's 1.10x). So a VPL does not reach a receiver across an
// emitter drawn this sample. Emitters not drawn this sample (more than Emissive Triangles of them) do not block: the
// leak is then reduced, not removed.
// Mirror: native/src/scene_lights.h, EmitterOccluder.
#include "common/emitter_occluders_shared.glsl"

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
// on, an emitter's own included, do not count). The CPU's twin: native/src/scene_lights.h, emitter_between.
bool emitter_between(vec3 y, vec3 x, float margin) {
  vec3 d = x - y;
  float length_d = length(d);
  if (!(length_d > 2.0 * margin)) return false;
  float t_min = margin / length_d, t_max = 1.0 - t_min;
  for (uint i = 0u; i < emitter_occluder_count.x; ++i)
    if (triangle_crosses_segment(emitter_occluders[i].a.xyz, emitter_occluders[i].b.xyz, emitter_occluders[i].c.xyz,
                                 y, d, t_min, t_max))
      return true;
  return false;
}
