// Ray Checks (native/src/passes/ray_checks/ray_checks.h): the light-pixel pairs whose visibility verdict a shadow
// ray checks on the CPU, the count first.
#include "common/random.glsl"

struct RayCheck {
  vec4 light_verdict;    // the light's position, the rule's verdict
  vec4 light_normal;     // w 1: the pair also corrects the pass's second image
  vec4 receiver;         // the pixel's surface point
  vec4 receiver_normal;
  vec3 unshadowed;       // the light's share of the pixel, unshadowed
  uint pixel;            // y * width + x
};
layout(std430, binding = 16) buffer RayChecks {
  uint ray_check_count;
  uint ray_check_pad[3];
  RayCheck ray_checks[];
};

// Whether the pair of a light at `light` and pixel `pixel` is checked this sample: a random share of them, drawn
// afresh with `sample_random`, lit or not by the rule.
bool ray_check_drawn(vec3 light, uint pixel, uint sample_random, float share) {
  return hash_to_unit(pcg_hash(floatBitsToUint(light.x) ^ pcg_hash(floatBitsToUint(light.z) ^ sample_random)) ^
                      pixel) < share;
}

void append_ray_check(vec3 light, vec3 light_normal, float verdict, vec3 receiver, vec3 receiver_normal,
                      vec3 unshadowed, uint pixel, bool marked) {
  uint slot = atomicAdd(ray_check_count, 1u);
  if (slot < uint(ray_checks.length()))
    ray_checks[slot] = RayCheck(vec4(light, verdict), vec4(light_normal, marked ? 1.0 : 0.0), vec4(receiver, 0.0),
                                vec4(receiver_normal, 0.0), unshadowed, pixel);
}
